/// \file bag_recorder_node.cpp
/// \brief main() of bag_recorder_node; everything else is in BagRecorder (src/ros).

#include <ros/ros.h>

#include "preadaptive_mrac/ros/bag_recorder.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "bag_recorder");
  return preadaptive_mrac::ros1::runBagRecorderNode();
}
