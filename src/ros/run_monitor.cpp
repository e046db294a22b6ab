#include "preadaptive_mrac/ros/run_monitor.hpp"

#include "preadaptive_mrac/ros/ros_params.hpp"

namespace preadaptive_mrac {
namespace ros1 {

RunMonitor::RunMonitor(const NodeContext& ctx, const std::vector<std::string>& topics) : ctx_(ctx) {
  ros::NodeHandle h(ctx.nh());
  watches_.resize(topics.size());
  for (size_t i = 0; i < topics.size(); ++i) {
    Watch* w = &watches_[i];
    w->topic = h.resolveName(topics[i]);
    w->sub = h.subscribe<PlantState>(
        topics[i], 100,
        [w](const PlantState::ConstPtr& m) {
          w->last_step = m->step;
          w->total = m->total_steps;
          if (m->total_steps > 0 && m->step + 1 >= m->total_steps) w->completed = true;
        },
        ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
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
    if (has_pub) w.seen_publisher = true;
    if (w.seen_publisher && !has_pub) {
      if (!w.completed) {
        ROS_ERROR("run_monitor: the plant on %s left at step %llu of %llu", w.topic.c_str(),
                  static_cast<unsigned long long>(w.last_step),
                  static_cast<unsigned long long>(w.total));
        done_ = true;
        timer_.stop();
        ctx_.end(kExitRuntimeError);
        return;
      }
    } else {
      all_done = false;
    }
  }
  if (all_done) {
    ROS_INFO("run_monitor: all %zu plant(s) finished", watches_.size());
    done_ = true;
    timer_.stop();
    ctx_.end(0);
  }
}

std::unique_ptr<RunMonitor> makeRunMonitor(const NodeContext& ctx) {
  XmlRpc::XmlRpcValue v;
  std::vector<std::string> topics;
  const std::string key = ctx.pnh().resolveName("state_topics");
  bool ok = ctx.pnh().getParam("state_topics", v) &&
            v.getType() == XmlRpc::XmlRpcValue::TypeArray && v.size() > 0;
  if (ok) {
    for (int i = 0; i < v.size(); ++i) {
      if (v[i].getType() != XmlRpc::XmlRpcValue::TypeString) {
        ok = false;
        break;
      }
      topics.push_back(static_cast<std::string>(v[i]));
    }
  }
  if (!ok) {
    ctx.logConfigProblems({key + ": expected a non-empty list of PlantState topic names"});
    ctx.end(kExitConfigError);
    return nullptr;
  }
  return std::make_unique<RunMonitor>(ctx, topics);
}

void RunMonitor::finish() {
  timer_.stop();
  for (auto& w : watches_) w.sub.shutdown();
}

int runRunMonitorNode() { return spinProcessNode(makeRunMonitor); }

}  // namespace ros1
}  // namespace preadaptive_mrac
