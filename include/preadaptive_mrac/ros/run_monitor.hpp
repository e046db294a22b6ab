#pragma once
/// \file run_monitor.hpp
/// \brief Waits until several plant nodes have finished their scenarios, so a launch file
/// with more than one plant (compare.launch) can mark this node `required` and return
/// when the last plant is done (a required plant would end the others' runs early).

#include <ros/ros.h>

#include <memory>
#include <string>
#include <vector>

#include "preadaptive_mrac/PlantState.h"
#include "preadaptive_mrac/ros/node_context.hpp"
#include "preadaptive_mrac/ros/publisher_guard.hpp"

namespace preadaptive_mrac {
namespace ros1 {

/// \brief Watches PlantState topics; done when every plant has published its last step
/// (step == total_steps - 1) and then left (no publisher on its topic any more). The last
/// state also comes latched on the sibling topic `done` (plant/state -> plant/done), so a
/// monitor that subscribed after the plant's last message (a lockstep run of a fraction of
/// a second in a nodelet manager, which the plant does not wait for) still sees it. A plant
/// that left before its last step is a failure only once it has been gone for kLeaveGrace
/// of wall time: the messages it sent before leaving may still wait in the queue (a loaded
/// machine, a plant that ran a lockstep scenario in a fraction of a second).
/// With ~accept_from only the listed publishers' states count; a watch whose plant has
/// published its last step is then done after kSettle even while a stray node still
/// publishes on the topic (its publisher would otherwise keep the run "running").
class RunMonitor {
 public:
  /// \brief topics: PlantState topics, resolved in ctx.nh()'s namespace. Ends the node
  /// (ctx.end) with 0 when every plant finished, kExitRuntimeError when a plant left before
  /// its last step; checked every 10 ms on ctx.nh()'s queue.
  RunMonitor(const NodeContext& ctx, const std::vector<std::string>& topics,
             const std::vector<std::string>& accept_from = {});
  /// \brief Stop watching.
  void finish();

 private:
  void check();

  struct Watch {
    ros::Subscriber sub, done_sub;
    std::string topic;
    bool seen_publisher = false, completed = false;
    std::uint64_t last_step = 0, total = 0;
    ros::WallTime gone_since;    ///< zero while a publisher is there
    ros::WallTime completed_at;  ///< when the last step was first seen
  };
  static constexpr double kLeaveGrace = 2.0;  ///< [s] wall
  static constexpr double kSettle = 0.5;      ///< [s] wall, guarded: completed to done
  NodeContext ctx_;
  PublisherGuard guard_;
  std::vector<Watch> watches_;
  ros::WallTimer timer_;
  bool done_ = false;
};

/// \brief The latched topic beside a PlantState topic with the plant's last state:
/// ".../state" -> ".../done", any other name + "/done".
std::string doneTopic(const std::string& state_topic);

/// \brief Read ~state_topics (readRunMonitorParams: a list of strings, required; refused:
/// ctx.end(kExitConfigError), nullptr) and start watching. Node and nodelet.
std::unique_ptr<RunMonitor> makeRunMonitor(const NodeContext& ctx);

/// \brief main() after ros::init(): makeRunMonitor, spin until it ends the node.
int runRunMonitorNode();

}  // namespace ros1
}  // namespace preadaptive_mrac
