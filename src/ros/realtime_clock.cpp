#include "preadaptive_mrac/ros/plant_clock.hpp"
#include "preadaptive_mrac/ros/plant_sim_node.hpp"
#include "preadaptive_mrac/ros/tick_source.hpp"

namespace preadaptive_mrac {
namespace ros1 {

RealtimeClock::RealtimeClock(PlantSimNode& node) : PlantClock(node) {}

bool RealtimeClock::take(const ElevatorCommand& msg, double arrival, double* latency_us) {
  // An answer to a state always supersedes a command of the controller's staleness timer
  // (whose step numbers run on by themselves and may be ahead).
  const PlantSimNode& n = node_;
  if (n.have_cmd_ && msg.step <= n.cmd_step_ && !(n.cmd_stale_ && !msg.stale)) {
    ++node_.commands_ignored_;
    return false;
  }
  // The command's stamp is the answered state's stamp, which realtime sets to the wall time
  // of publication.
  *latency_us = 1e6 * (arrival - msg.header.stamp.toSec());
  return true;
}

bool RealtimeClock::heldCommand(double first_cmd_deadline, double* u) {
  PlantSimNode& n = node_;
  const PlantNodeParams& p = n.params_;
  if (!n.have_cmd_ && first_cmd_deadline > 0.0 && wallNow() > first_cmd_deadline) {
    ROS_ERROR(
        "no valid command on %s within %.1f s of the first state (~start_timeout): %s; "
        "giving up (exit code %d)",
        n.cmd_sub_.getTopic().c_str(), p.start_timeout, n.noCommandCause("does not answer").c_str(),
        kExitRuntimeError);
    return false;
  }
  if (!n.have_cmd_ || n.cmd_step_ != static_cast<std::uint64_t>(n.sim_.step())) ++stale_steps_;
  // Zero-order hold on the latest valid command while it is fresh; without one (none yet,
  // the controller gone, or only rejected ones) hold trim rather than an old u.
  const bool fresh = n.have_cmd_ && wallNow() - n.last_cmd_wall_ <= p.cmd_timeout;
  *u = fresh ? n.cmd_u_ : 0.0;
  if (!fresh) {
    ++trim_steps_;
    if (!in_trim_ && n.have_cmd_) {
      ++trim_episodes_;
      ROS_WARN("no valid command for %.3f s (~cmd_timeout %.3f s): holding trim (u = 0)",
               wallNow() - n.last_cmd_wall_, p.cmd_timeout);
    }
  } else if (in_trim_) {
    ROS_INFO("commands are back after %lld trim step(s)", static_cast<long long>(trim_steps_));
  }
  in_trim_ = !fresh;
  return true;
}

int RealtimeClock::run() {
  PlantSimNode& n = node_;
  if (!n.waitForSubscribers()) return kExitRuntimeError;
  // The tick thread (this one): optional SCHED_FIFO priority and CPU affinity; a refusal is a
  // warning and normal scheduling.
  // In a process of its own also roscpp's receiving thread, which reads each command first.
  n.schedule(n.params_.rt_priority, !n.ctx_.isNodelet());
  // Absolute deadlines (clock_nanosleep TIMER_ABSTIME): a late tick does not shift the later
  // ones, so 60 s of ticks take 60 s.
  TickSource ticks(1.0 / n.params_.rate);
  n.wall_start_ = wallNow();
  ticks.start();
  n.publishSample(ros::Time(ros::WallTime::now().toSec()));
  // A controller that subscribed and then died (or never answers) would leave the plant
  // holding trim through the whole scenario: give up unless one valid command arrives.
  const double first_cmd_deadline =
      n.params_.start_timeout > 0.0 ? n.wall_start_ + n.params_.start_timeout : 0.0;
  bool gave_up = false;
  while (n.ctx_.ok()) {
    // This thread takes the commands itself (no spinner thread in between) until the answer
    // to the current step is in or the tick is nearly due (kept 50 us for the wake-up).
    const std::int64_t serve_until = ticks.nextDeadlineNs() - 50000;
    while (n.ctx_.ok()) {
      {
        std::lock_guard<std::mutex> lock(n.mutex_);
        if (n.have_cmd_ && n.cmd_step_ == static_cast<std::uint64_t>(n.sim_.step())) break;
      }
      const std::int64_t left = serve_until - monotonicNs();
      if (left <= 0) break;
      n.queue_.callAvailable(ros::WallDuration(static_cast<double>(left) * 1e-9));
    }
    const double late_us = 1e6 * ticks.waitNext();
    double u = 0.0;
    {
      std::lock_guard<std::mutex> lock(n.mutex_);
      tick_late_us_.add(late_us);
      // Behind schedule the ticks run back to back until the simulation has caught up.
      if (ticks.late()) ++late_ticks_;
      gave_up = !heldCommand(first_cmd_deadline, &u);
    }
    if (gave_up) break;
    n.advance(u);
    n.updater_.update();
    if (n.sim_.done()) break;
    const ros::WallTime now = ros::WallTime::now();
    n.publishSample(ros::Time(now.sec, now.nsec));
    if (n.sim_.nonFinite()) break;  // its sample published: the run ends (finish: stopped)
  }
  n.finish(n.sim_.done());
  if (gave_up || n.sim_.nonFinite()) return kExitRuntimeError;
  n.linger();
  return 0;
}

void RealtimeClock::problems(NodeStatus& status) const {
  status.problem(in_trim_ && node_.have_cmd_, diagnostic_msgs::DiagnosticStatus::ERROR,
                 "no valid command within ~cmd_timeout: holding trim");
}

void RealtimeClock::rows(NodeStatus& status) const {
  status.rows({{"holding trim", in_trim_},
               {"trim steps", trim_steps_},
               {"trim episodes", trim_episodes_},
               {"stale steps", stale_steps_},
               {"late ticks", late_ticks_}});
}

void RealtimeClock::report(RunReport* r) const {
  r->rate_hz = node_.params_.rate;
  r->stale_steps = stale_steps_;
  r->late_ticks = late_ticks_;
  r->tick_late = tick_late_us_.summary();
}

}  // namespace ros1
}  // namespace preadaptive_mrac
