#include "preadaptive_mrac/ros/run_monitor.hpp"

#include <algorithm>

#include "preadaptive_mrac/ros/node_params.hpp"
#include "preadaptive_mrac/ros/ros_params.hpp"

namespace preadaptive_mrac {
namespace ros1 {

std::string doneTopic(const std::string& state_topic) {
  const std::string suffix = "/state";
  if (state_topic.size() > suffix.size() &&
      state_topic.compare(state_topic.size() - suffix.size(), suffix.size(), suffix) == 0)
    return state_topic.substr(0, state_topic.size() - suffix.size()) + "/done";
  return state_topic + "/done";
}

RunMonitor::RunMonitor(const NodeContext& ctx, const std::vector<std::string>& topics,
                       const std::vector<std::string>& accept_from)
    : ctx_(ctx), guard_(makePublisherGuard(ctx, accept_from)) {
  ros::NodeHandle h(ctx.nh());
  watches_.resize(topics.size());
  for (size_t i = 0; i < topics.size(); ++i) {
    Watch* w = &watches_[i];
    w->topic = h.resolveName(topics[i]);
    auto on_state = [this, w](const ros::MessageEvent<const PlantState>& event) {
      if (!guard_.admitEvent(event, w->topic)) return;
      const PlantState& m = *event.getConstMessage();
      w->last_step = std::max(w->last_step, static_cast<std::uint64_t>(m.step));
      w->total = m.total_steps;
      if (m.total_steps > 0 && m.step + 1 >= m.total_steps && !w->completed) {
        w->completed = true;
        w->completed_at = ros::WallTime::now();
      }
    };
    const boost::function<void(const ros::MessageEvent<const PlantState>&)> callback(on_state);
    w->sub = h.subscribe<PlantState>(topics[i], 100, callback, ros::VoidConstPtr(),
                                     ros::TransportHints().tcpNoDelay());
    w->done_sub = h.subscribe<PlantState>(doneTopic(w->topic), 1, callback);
  }
  // Polled on the same queue as the subscriptions, so the watches need no lock.
  timer_ =
      h.createWallTimer(ros::WallDuration(0.01), [this](const ros::WallTimerEvent&) { check(); });
}

void RunMonitor::check() {
  if (done_) return;
  bool all_done = true;
  for (auto& w : watches_) {
    const bool has_pub = w.sub.getNumPublishers() > 0;
    // Guarded, a finished plant is done once settled whoever else still publishes.
    if (w.completed && guard_.enabled() &&
        (ros::WallTime::now() - w.completed_at).toSec() >= kSettle)
      continue;
    if (has_pub) {
      w.seen_publisher = true;
      w.gone_since = ros::WallTime();
      all_done = false;
      continue;
    }
    if (w.completed) continue;  // finished and left (its last state came on either topic)
    all_done = false;
    if (!w.seen_publisher) continue;  // not started yet
    // Left before its last step, as far as the messages handled so far say: those it sent
    // before leaving may still wait in the queue, so judge only after kLeaveGrace.
    const ros::WallTime now = ros::WallTime::now();
    if (w.gone_since.isZero()) w.gone_since = now;
    if ((now - w.gone_since).toSec() < kLeaveGrace) continue;
    ROS_ERROR("run_monitor: the plant on %s left at step %llu of %llu", w.topic.c_str(),
              static_cast<unsigned long long>(w.last_step),
              static_cast<unsigned long long>(w.total));
    done_ = true;
    timer_.stop();
    ctx_.end(kExitRuntimeError);
    return;
  }
  if (all_done) {
    ROS_INFO("run_monitor: all %zu plant(s) finished", watches_.size());
    done_ = true;
    timer_.stop();
    ctx_.end(0);
  }
}

std::unique_ptr<RunMonitor> makeRunMonitor(const NodeContext& ctx) {
  RunMonitorParams p;
  if (!readNodeParams(ctx, readRunMonitorParams, &p)) return nullptr;
  return std::make_unique<RunMonitor>(ctx, p.state_topics, p.accept_from);
}

void RunMonitor::finish() {
  timer_.stop();
  for (auto& w : watches_) w.sub.shutdown();
}

int runRunMonitorNode() { return spinProcessNode(makeRunMonitor); }

}  // namespace ros1
}  // namespace preadaptive_mrac
