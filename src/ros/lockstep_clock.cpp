#include <rosgraph_msgs/Clock.h>
#include <std_msgs/Bool.h>

#include <algorithm>
#include <functional>

#include "preadaptive_mrac/ros/plant_clock.hpp"
#include "preadaptive_mrac/ros/plant_sim_node.hpp"

namespace preadaptive_mrac {
namespace ros1 {
namespace {

/// How long the plant waits for the recorder to write the command of step 0 before it
/// publishes state 0 again [s].
constexpr double kFirstCommandResend = 0.02;

}  // namespace

LockstepClock::LockstepClock(PlantSimNode& node) : PlantClock(node) {
  const PlantNodeParams& p = node_.params_;
  if (p.publish_clock) {
    // Latched, so a node that starts late (rosbag waits for a valid clock before it
    // subscribes to anything) sees the current time at once.
    clock_pub_ = node_.nh_.advertise<rosgraph_msgs::Clock>("clock", 10, true);
  }
  if (p.wait_for_controller) {
    node_.ready_sub_ = node_.own_.subscribe<std_msgs::Bool>(
        "controller/ready", 1, [this](const std_msgs::Bool::ConstPtr& m) {
          if (m->data) node_.controller_ready_ = true;
        });
  }
}

bool LockstepClock::take(const ElevatorCommand& msg, double arrival, double* latency_us) {
  if (msg.stale) {
    // The controller's staleness timer: not an answer to a state; lockstep keeps waiting.
    ++stale_cmds_ignored_;
    return false;
  }
  const auto expected = static_cast<std::uint64_t>(node_.sim_.step());
  // A second answer to the awaited step (to its state published again) changes nothing.
  if (!node_.sim_.done() && msg.step == expected && node_.have_cmd_ && node_.cmd_step_ == expected)
    return false;
  if (node_.sim_.done() || msg.step != expected) {
    ++node_.commands_ignored_;
    ROS_WARN_THROTTLE(1.0, "ignoring command for step %llu (waiting for step %llu)",
                      static_cast<unsigned long long>(msg.step),
                      static_cast<unsigned long long>(expected));
    return false;
  }
  // Only the awaited step's state is ever answered; a resend keeps its first publication.
  *latency_us = published_step_ == expected ? 1e6 * (arrival - published_wall_) : 0.0;
  return true;
}

void LockstepClock::progress(const RecorderProgress& msg) {
  std::lock_guard<std::mutex> lock(node_.mutex_);
  if (msg.topic == node_.cmd_topic_) {
    if (!have_cmd_progress_ || msg.step > recorded_cmd_step_) recorded_cmd_step_ = msg.step;
    have_cmd_progress_ = true;
    return;
  }
  if (!have_progress_ || msg.step > recorded_step_) recorded_step_ = msg.step;
  have_progress_ = true;
}

bool LockstepClock::serveUntil(const std::function<bool()>& done, double slice,
                               const std::function<void(double)>& between) {
  PlantSimNode& n = node_;
  const double deadline = wallNow() + n.params_.command_timeout;
  while (n.ctx_.ok()) {
    if (done()) return true;
    const double now = wallNow();
    if (now >= deadline) return false;
    if (between) between(now);
    n.queue_.callAvailable(ros::WallDuration(std::min(deadline - now, slice)));
  }
  return false;
}

void LockstepClock::waitForRecordedFirstCommand() {
  PlantSimNode& n = node_;
  if (!n.connections_sub_ || !n.recorder_records_commands_) return;
  const auto written = [&] {
    std::lock_guard<std::mutex> lock(n.mutex_);
    return have_cmd_progress_;
  };
  if (written()) return;
  {
    std::lock_guard<std::mutex> lock(n.mutex_);
    ++recorder_waits_;
  }
  double again_at = wallNow() + kFirstCommandResend;
  const auto publish_again = [&](double now) {
    if (now < again_at) return;
    n.state_pub_.publish(n.last_state_);
    again_at = now + kFirstCommandResend;
  };
  if (!serveUntil(written, 0.005, publish_again) && n.ctx_.ok())
    ROS_WARN(
        "the recorder has not written the command of step 0 on %s after %.3f s "
        "(~command_timeout); going on without it",
        n.cmd_topic_.c_str(), n.params_.command_timeout);
}

void LockstepClock::waitForRecordedCommands() {
  PlantSimNode& n = node_;
  const auto done = [&] {
    std::lock_guard<std::mutex> lock(n.mutex_);
    return !have_cmd_progress_ || !n.have_cmd_ || recorded_cmd_step_ >= n.cmd_step_;
  };
  if (serveUntil(done, 0.01, nullptr) || !n.ctx_.ok()) return;
  std::lock_guard<std::mutex> lock(n.mutex_);
  ROS_WARN(
      "the recorder has written command step %llu of %s, not yet the last one taken "
      "(%llu), after %.3f s (~command_timeout); ending anyway",
      static_cast<unsigned long long>(recorded_cmd_step_), n.cmd_topic_.c_str(),
      static_cast<unsigned long long>(n.cmd_step_), n.params_.command_timeout);
}

void LockstepClock::published(std::uint64_t step, double wall) {
  published_step_ = step;
  published_wall_ = wall;
}

bool LockstepClock::waitForRecorder(std::uint64_t step, std::uint64_t lag) {
  if (!node_.progress_sub_) return true;
  const std::uint64_t needed = step > lag ? step - lag : 0;
  const auto caught_up = [&] {
    std::lock_guard<std::mutex> lock(node_.mutex_);
    return have_progress_ && recorded_step_ >= needed;
  };
  if (step < lag || caught_up()) return true;
  const auto count_wait = [&](double) {
    std::lock_guard<std::mutex> lock(node_.mutex_);
    ++recorder_waits_;
  };
  if (serveUntil(caught_up, 0.1, count_wait)) return true;
  if (!node_.ctx_.ok()) return false;
  std::lock_guard<std::mutex> lock(node_.mutex_);
  ROS_ERROR(
      "the recorder (%s) has written step %llu of %s, needed %llu, and made no "
      "progress for %.3f s (~command_timeout); stopping",
      node_.progress_sub_.getTopic().c_str(), static_cast<unsigned long long>(recorded_step_),
      node_.state_pub_.getTopic().c_str(), static_cast<unsigned long long>(needed),
      node_.params_.command_timeout);
  return false;
}

bool LockstepClock::awaitAnswer(std::uint64_t k, double* u, bool* give_up) {
  PlantSimNode& n = node_;
  const PlantNodeParams& p = n.params_;
  const double deadline = wallNow() + p.command_timeout;
  double resend_at = p.resend_interval > 0.0 ? wallNow() + p.resend_interval : deadline;
  while (n.ctx_.ok()) {
    {
      std::lock_guard<std::mutex> lock(n.mutex_);
      if (n.have_cmd_ && n.cmd_step_ == k) {
        *u = n.cmd_u_;
        return true;
      }
    }
    const double now = wallNow();
    if (now >= deadline) {
      ROS_ERROR(
          "no command for step %llu (t = %.6f s) on %s within %.3f s "
          "(~command_timeout): %s; stopping (exit code %d)",
          static_cast<unsigned long long>(k), n.sim_.time(), n.cmd_sub_.getTopic().c_str(),
          p.command_timeout, n.noCommandCause("did not answer").c_str(), kExitRuntimeError);
      *give_up = true;
      return false;
    }
    if (now >= resend_at) {
      // The state was lost, or reached the controller before it subscribed (an extra
      // subscriber can make the start-up count look complete). The same message again, and
      // only the state (nothing waits on the truth or tf): the controller ignores a repeat
      // and the recorder does not write it twice.
      ROS_WARN("no command for step %llu after %.3f s: publishing its state again",
               static_cast<unsigned long long>(k), p.resend_interval);
      {
        std::lock_guard<std::mutex> lock(n.mutex_);
        ++resent_;
      }
      n.state_pub_.publish(n.last_state_);
      resend_at = now + p.resend_interval;
    }
    // Blocks until a callback is queued (or the bounded wait ends): no polling delay. A
    // controller in this process has answered already (its callback ran in this thread).
    n.queue_.callAvailable(ros::WallDuration(std::min(std::min(deadline, resend_at) - now, 0.1)));
  }
  return false;
}

int LockstepClock::run() {
  PlantSimNode& n = node_;
  if (clock_pub_) {
    rosgraph_msgs::Clock c;
    c.clock = PlantSimNode::simStamp(0.0);
    clock_pub_.publish(c);
  }
  if (!n.waitForSubscribers()) return kExitRuntimeError;
  // ~cpu_affinity (not ~rt_priority: lockstep has no deadlines): with the controller's thread
  // pinned to the same CPU each hand-off of the round trip is a switch on that CPU, not a
  // wake-up of another (docs/reference/ros.md).
  n.schedule(0, false);
  n.wall_start_ = wallNow();
  rosgraph_msgs::Clock clock_msg;
  const auto lag = static_cast<std::uint64_t>(n.params_.max_recorder_lag);
  const auto clock_every = static_cast<std::uint64_t>(n.params_.clock_decimation);
  const auto total = static_cast<std::uint64_t>(n.sim_.totalSteps());
  while (n.ctx_.ok() && !n.sim_.done()) {
    const auto k = static_cast<std::uint64_t>(n.sim_.step());
    // Back-pressure: a recorder that falls too far behind would hold an ever larger backlog
    // in this process, lost if the run ends before it is sent.
    if (!waitForRecorder(k, lag)) {
      n.finish(false);
      return kExitRuntimeError;
    }
    const ros::Time stamp = PlantSimNode::simStamp(n.sim_.time());
    if (clock_pub_ && (k % clock_every == 0 || k + 1 == total)) {
      clock_msg.clock = stamp;
      clock_pub_.publish(clock_msg);
    }
    n.publishSample(stamp);
    double u = 0.0;
    bool give_up = false;
    if (!awaitAnswer(k, &u, &give_up)) {
      if (!give_up) break;  // shutdown requested
      n.finish(false);
      return kExitRuntimeError;
    }
    if (k == 0) waitForRecordedFirstCommand();
    n.advance(u);
    n.updater_.update();
    if (n.sim_.nonFinite()) {
      // Nothing after a non-finite state means anything: its sample (the truth says why) is
      // published and recorded, and the run ends as stopped.
      n.publishSample(PlantSimNode::simStamp(n.sim_.time()));
      waitForRecorder(static_cast<std::uint64_t>(n.sim_.step()), 0);
      n.finish(false);
      return kExitRuntimeError;
    }
  }
  // The bag must hold the last state before this node (and so the run) ends.
  if (n.sim_.done() && !waitForRecorder(total - 1, 0)) {
    n.finish(false);
    return kExitRuntimeError;
  }
  if (n.sim_.done()) waitForRecordedCommands();
  n.finish(n.sim_.done());
  n.linger();
  return 0;
}

void LockstepClock::rows(NodeStatus& status) const {
  status.rows({{"stale commands ignored (lockstep)", stale_cmds_ignored_},
               {"resent states", resent_},
               {"waits for the recorder", recorder_waits_}});
}

void LockstepClock::report(RunReport* r) const {
  r->resent_states = resent_;
  r->recorder_waits = recorder_waits_;
}

std::unique_ptr<PlantClock> makePlantClock(PlantSimNode& node) {
  if (node.params_.clock == ClockMode::kLockstep) return std::make_unique<LockstepClock>(node);
  return std::make_unique<RealtimeClock>(node);
}

}  // namespace ros1
}  // namespace preadaptive_mrac
