#pragma once
/// \file run_monitor.hpp
/// \brief Waits until several plant nodes have finished their scenarios, so a launch file
/// with more than one plant (compare.launch) can mark this node `required` and return
/// when the last plant is done (a required plant would end the others' runs early).

#include <ros/ros.h>

#include <string>
#include <vector>

#include "preadaptive_mrac/PlantState.h"

namespace preadaptive_mrac {
namespace ros1 {

/// \brief Watches PlantState topics; done when every plant has published its last step
/// (step == total_steps - 1) and then left (no publisher on its topic any more).
class RunMonitor {
 public:
  /// \brief topics: PlantState topics, resolved in nh's namespace.
  RunMonitor(const ros::NodeHandle& nh, const std::vector<std::string>& topics);
  /// \brief Spin until every plant finished (returns 0), a plant left before its last step
  /// (kExitRuntimeError), or shutdown (0).
  int run();

 private:
  struct Watch {
    ros::Subscriber sub;
    std::string topic;
    bool seen_publisher = false, completed = false;
    std::uint64_t last_step = 0, total = 0;
  };
  std::vector<Watch> watches_;
};

/// \brief main() after ros::init(): reads ~state_topics (list of strings, required).
int runRunMonitorNode();

}  // namespace ros1
}  // namespace preadaptive_mrac
