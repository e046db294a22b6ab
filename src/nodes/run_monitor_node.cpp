/// \file run_monitor_node.cpp
/// \brief main() of run_monitor_node; everything else is in RunMonitor (src/ros).

#include <ros/ros.h>

#include "preadaptive_mrac/ros/run_monitor.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "run_monitor");
  return preadaptive_mrac::ros1::runRunMonitorNode();
}
