/// \file mrac_controller_node.cpp
/// \brief main() of mrac_controller_node; everything else is in MracControllerNode (src/ros).

#include "preadaptive_mrac/ros/mrac_controller_node.hpp"

#include <ros/ros.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "mrac_controller");
  return preadaptive_mrac::ros1::runMracControllerNode();
}
