#include "preadaptive_mrac/ros/plant_sim_node.hpp"

#include <geometry_msgs/TransformStamped.h>
#include <ros/callback_queue.h>
#include <rosgraph_msgs/Clock.h>
#include <std_msgs/Bool.h>
#include <tf2_msgs/TFMessage.h>

#include <boost/make_shared.hpp>
#include <cmath>
#include <fstream>

#include "preadaptive_mrac/ros/ros_params.hpp"

namespace preadaptive_mrac {
namespace ros1 {
namespace {

constexpr uint32_t kCommandQueue = 100;

double wallNow() { return ros::WallTime::now().toSec(); }

geometry_msgs::TransformStamped pitchTransform(const ros::Time& stamp, const std::string& parent,
                                               const std::string& child, double angle) {
  // Rotation about the parent's y axis by `angle`. With REP 103 axes (x forward, y left,
  // z up) a nose-up pitch is a negative rotation about y.
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform.rotation.x = 0.0;
  t.transform.rotation.y = std::sin(0.5 * angle);
  t.transform.rotation.z = 0.0;
  t.transform.rotation.w = std::cos(0.5 * angle);
  return t;
}

}  // namespace

PlantSimNode::PlantSimNode(const NodeContext& ctx, const PlantNodeParams& params)
    : ctx_(ctx),
      nh_(ctx.nh()),
      params_(params),
      sim_(params.run.plant, params.run.scenario, params.dt),
      updater_(ros::NodeHandle(), ctx.pnh(), ctx.name()),
      cmd_guard_(makePublisherGuard(ctx, params.accept_from)) {
  // The plant's own subscriptions go to a queue that only its loop serves: in lockstep the
  // loop takes each command as soon as it is queued, with no other thread in between, in a
  // process of its own and in a shared nodelet manager alike.
  ros::NodeHandle own(nh_);
  own.setCallbackQueue(&queue_);
  updater_.setHardwareID("plant_sim");
  updater_.add("plant", this, &PlantSimNode::diagnose);
  // ~queue_size bounds the backlog kept for each slow subscriber (a recorder under load falls
  // seconds behind a lockstep run); 0 keeps everything, so no sample is lost.
  const auto q = static_cast<uint32_t>(params_.queue_size);
  state_pub_ = nh_.advertise<PlantState>("plant/state", q);
  truth_pub_ = nh_.advertise<PlantTruth>("plant/truth", q);
  done_pub_ = nh_.advertise<PlantState>("plant/done", 1, /*latch=*/true);
  if (params_.clock == ClockMode::kLockstep && params_.publish_clock) {
    // Latched, so a node that starts late (rosbag waits for a valid clock before it
    // subscribes to anything) sees the current time at once.
    clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("clock", 10, true);
  }
  tf_pub_ = nh_.advertise<tf2_msgs::TFMessage>("tf", 100);
  cmd_sub_ = own.subscribe("controller/elevator_cmd", kCommandQueue, &PlantSimNode::commandCallback,
                           this, ros::TransportHints().tcpNoDelay());
  cmd_topic_ = cmd_sub_.getTopic();
  if (cmd_guard_.enabled())
    ROS_INFO("taking commands on %s only from %s (~accept_from)", cmd_topic_.c_str(),
             cmd_guard_.acceptedText().c_str());
  if (params_.wait_for_controller && params_.clock == ClockMode::kLockstep) {
    ready_sub_ = own.subscribe<std_msgs::Bool>("controller/ready", 1,
                                               [this](const std_msgs::Bool::ConstPtr& m) {
                                                 if (m->data) controller_ready_ = true;
                                               });
  }
  if (!params_.recorder_progress_topic.empty()) {
    progress_sub_ =
        own.subscribe(params_.recorder_progress_topic, 100, &PlantSimNode::progressCallback, this,
                      ros::TransportHints().tcpNoDelay());
  }
  latency_us_.reserve(static_cast<size_t>(sim_.totalSteps()));
  if (params_.clock == ClockMode::kRealtime)
    tick_late_us_.reserve(static_cast<size_t>(sim_.totalSteps()));
  if (params_.clock == ClockMode::kLockstep)
    publish_wall_.assign(static_cast<size_t>(sim_.totalSteps()), 0.0);
  // Pitch angle theta = gamma + alpha: start on a level flight path (gamma(0) = 0).
  const int out = sim_.plant().outputIndex();
  theta_pitch_ = sim_.state()[out];
}

ros::Time PlantSimNode::simStamp(double t) {
  ros::Time s(t);
  // ROS reads time 0 as "no clock yet" (rosbag record would not start), so step 0 is 1 ns.
  if (s.isZero()) s = ros::Time(0, 1);
  return s;
}

void PlantSimNode::commandCallback(const ros::MessageEvent<ElevatorCommand const>& event) {
  // ~accept_from: a command from another node is dropped before anything else, so it can
  // neither answer a lockstep step nor count as fresh in realtime (trim still comes).
  if (!cmd_guard_.admitEvent(event, cmd_topic_)) return;
  const ElevatorCommand::ConstPtr msg = event.getConstMessage();
  const double arrival = wallNow();
  std::lock_guard<std::mutex> lock(mutex_);
  if (!std::isfinite(msg->u)) {
    // Never applied, and it does not count as a fresh command (realtime trim still runs).
    ++commands_rejected_;
    last_rejection_ = "step " + std::to_string(msg->step) + ": u is " + std::to_string(msg->u);
    ROS_ERROR_THROTTLE(1.0, "command for step %llu rejected: u is not finite (%lld so far)",
                       static_cast<unsigned long long>(msg->step),
                       static_cast<long long>(commands_rejected_));
    return;
  }
  if (params_.clock == ClockMode::kLockstep) {
    if (msg->stale) {
      // The controller's staleness timer: not an answer to a state; lockstep keeps waiting.
      ++stale_cmds_ignored_;
      return;
    }
    const auto expected = static_cast<std::uint64_t>(sim_.step());
    if (sim_.done() || msg->step != expected) {
      ++commands_ignored_;
      ROS_WARN_THROTTLE(1.0, "ignoring command for step %llu (waiting for step %llu)",
                        static_cast<unsigned long long>(msg->step),
                        static_cast<unsigned long long>(expected));
      return;
    }
    latency_us_.push_back(1e6 * (arrival - publish_wall_[static_cast<size_t>(expected)]));
  } else {
    // The command's stamp is the answered state's stamp, which realtime sets to the wall
    // time of publication.
    // An answer to a state always supersedes a command of the controller's staleness timer
    // (whose step numbers run on by themselves and may be ahead).
    if (have_cmd_ && msg->step <= cmd_step_ && !(cmd_stale_ && !msg->stale)) {
      ++commands_ignored_;
      return;
    }
    latency_us_.push_back(1e6 * (arrival - msg->header.stamp.toSec()));
  }
  ++commands_received_;
  have_cmd_ = true;
  cmd_step_ = msg->step;
  cmd_u_ = msg->u;
  cmd_stale_ = msg->stale;
  last_cmd_wall_ = arrival;
}

void PlantSimNode::progressCallback(const RecorderProgress::ConstPtr& msg) {
  // Realtime only waits for the recorder to exist before step 0 (waitForSubscribers).
  if (params_.clock != ClockMode::kLockstep) return;
  if (msg->topic != state_pub_.getTopic()) return;  // another plant's progress
  std::lock_guard<std::mutex> lock(mutex_);
  if (!have_progress_ || msg->step > recorded_step_) recorded_step_ = msg->step;
  have_progress_ = true;
}

bool PlantSimNode::waitForRecorder(std::uint64_t step, std::uint64_t lag) {
  if (!progress_sub_ || params_.clock != ClockMode::kLockstep) return true;
  const std::uint64_t needed = step > lag ? step - lag : 0;
  const auto caught_up = [&] {
    std::lock_guard<std::mutex> lock(mutex_);
    return have_progress_ && recorded_step_ >= needed;
  };
  if (step < lag || caught_up()) return true;
  const double deadline = wallNow() + params_.command_timeout;
  while (ctx_.ok()) {
    if (caught_up()) return true;
    const double remaining = deadline - wallNow();
    if (remaining <= 0.0) {
      std::lock_guard<std::mutex> lock(mutex_);
      ROS_ERROR(
          "the recorder (%s) has written step %llu of %s, needed %llu, and made no "
          "progress for %.3f s (~command_timeout); stopping",
          progress_sub_.getTopic().c_str(), static_cast<unsigned long long>(recorded_step_),
          state_pub_.getTopic().c_str(), static_cast<unsigned long long>(needed),
          params_.command_timeout);
      return false;
    }
    ++recorder_waits_;
    queue_.callAvailable(ros::WallDuration(std::min(remaining, 0.1)));
  }
  return false;
}

bool PlantSimNode::waitForSubscribers() {
  const double start = wallNow();
  const double timeout = params_.start_timeout;
  ROS_INFO("waiting for %d subscriber(s) on %s and %d on %s (timeout %s)",
           params_.min_state_subscribers, state_pub_.getTopic().c_str(),
           params_.min_truth_subscribers, truth_pub_.getTopic().c_str(),
           timeout > 0.0 ? (std::to_string(timeout) + " s, ~start_timeout").c_str() : "none");
  bool warned = false;
  while (ctx_.ok()) {
    // A recorder advertises its progress once it has subscribed to everything: in a nodelet
    // manager its subscriptions share the connection of the controller's and are not counted.
    if (static_cast<int>(state_pub_.getNumSubscribers()) >= params_.min_state_subscribers &&
        static_cast<int>(truth_pub_.getNumSubscribers()) >= params_.min_truth_subscribers &&
        (!progress_sub_ || progress_sub_.getNumPublishers() > 0) &&
        (!ready_sub_ || controller_ready_))
      return true;
    const double waited = wallNow() - start;
    if (timeout > 0.0 && !warned && waited > 0.5 * timeout) {
      warned = true;
      ROS_WARN("still waiting for subscribers after %.1f s: %s (giving up after %.1f s)", waited,
               missingPeers().c_str(), timeout);
    }
    if (timeout > 0.0 && waited > timeout) {
      ROS_ERROR("no controller after %.1f s (~start_timeout): %s; giving up (exit code %d)",
                timeout, missingPeers().c_str(), kExitRuntimeError);
      return false;
    }
    // Connections are made by roscpp's own threads; poll them in short bounded waits (and
    // take controller/ready, which comes on this node's own queue).
    if (ready_sub_)
      queue_.callAvailable(ros::WallDuration(0.002));
    else
      ros::WallDuration(0.002).sleep();
  }
  return false;
}

std::string PlantSimNode::missingPeers() const {
  std::string s = std::to_string(state_pub_.getNumSubscribers()) + " of " +
                  std::to_string(params_.min_state_subscribers) + " subscriber(s) on " +
                  state_pub_.getTopic() +
                  " (~min_state_subscribers: the controller, recorders and watchers), " +
                  std::to_string(truth_pub_.getNumSubscribers()) + " of " +
                  std::to_string(params_.min_truth_subscribers) + " on " + truth_pub_.getTopic();
  if (progress_sub_ && progress_sub_.getNumPublishers() == 0)
    s += "; no recorder publishes " + progress_sub_.getTopic();
  if (ready_sub_ && !controller_ready_)
    s += "; the controller has not said it takes states on " + ready_sub_.getTopic() +
         " (~wait_for_controller)";
  if (cmd_sub_.getNumPublishers() == 0) {
    s += "; no node publishes " + cmd_sub_.getTopic() +
         ": the controller is not running (one that refuses its parameters exits with code 2 "
         "naming each key: see its output)";
  } else {
    s += "; a controller publishes " + cmd_sub_.getTopic() +
         " but has not subscribed (it waits for its own subscribers first, e.g. a recorder)";
  }
  return s;
}

std::string PlantSimNode::noCommandCause(const char* silent) const {
  std::string s = cmd_sub_.getNumPublishers() == 0
                      ? "no node publishes it: no controller (or it has gone)"
                      : std::string("the controller is connected but ") + silent;
  // A ~accept_from that does not name the controller's caller id drops every answer.
  if (cmd_guard_.dropped() > 0)
    s += "; commands dropped as not from ~accept_from (" + cmd_guard_.acceptedText() +
         "): " + cmd_guard_.droppedText();
  return s;
}

void PlantSimNode::publishSample(const ros::Time& stamp) {
  const auto k = static_cast<std::uint64_t>(sim_.step());
  // What a sensor reports (state + the configured noise); the true state stays in the core.
  const Vec& x = sim_.measured();
  const Vec& theta = sim_.theta();
  const int out = sim_.plant().outputIndex();

  // Each message is built once and never touched after publishing: subscribers in the same
  // process (nodelets) get the pointer, without serialisation or copy.
  const auto truth = boost::make_shared<PlantTruth>();
  truth->header.stamp = stamp;
  truth->step = k;
  truth->theta.assign(theta.data(), theta.data() + theta.size());
  truth->theta_scale = theta.size() > 0 ? theta[0] : 0.0;
  truth->effectiveness = sim_.effectiveness();
  truth->gust_w = sim_.gust();
  truth->gust_alpha = sim_.gustAlpha();
  truth_pub_.publish(PlantTruth::ConstPtr(truth));

  const auto state = boost::make_shared<PlantState>();
  state->header.stamp = stamp;
  state->step = k;
  state->t = sim_.time();
  state->dt = sim_.dt();
  state->total_steps = static_cast<std::uint64_t>(sim_.totalSteps());
  state->x.assign(x.data(), x.data() + x.size());
  state->e_I = x.size() > 0 ? x[0] : 0.0;
  state->alpha = x[out];
  state->q = x.size() > 2 ? x[2] : 0.0;
  state->theta_pitch = theta_pitch_;
  state->r = sim_.reference();
  state->elevator = applied_u_;
  state->elevator_command = sim_.lastCommand();
  if (params_.clock == ClockMode::kLockstep) publish_wall_[static_cast<size_t>(k)] = wallNow();
  last_state_ = state;
  state_pub_.publish(last_state_);

  if (k % static_cast<std::uint64_t>(params_.tf_decimation) == 0) {
    const auto tfs = boost::make_shared<tf2_msgs::TFMessage>();
    tfs->transforms.push_back(
        pitchTransform(stamp, params_.world_frame, params_.body_frame, -theta_pitch_));
    // The velocity vector lies alpha below the nose: rotate the body frame nose-down by alpha.
    tfs->transforms.push_back(
        pitchTransform(stamp, params_.body_frame, params_.velocity_frame, x[out]));
    tf_pub_.publish(tf2_msgs::TFMessage::ConstPtr(tfs));
  }
}

void PlantSimNode::advance(double u) {
  const double q_before = sim_.state().size() > 2 ? sim_.state()[2] : 0.0;
  sim_.advance(u);
  // After the actuator limits of plant.actuator (u itself when they are off).
  applied_u_ = sim_.lastApplied();
  // What the limits did, not applied != commanded: with a servo delay or lag the deflection
  // differs from the command in nearly every step without any limit being reached.
  if (sim_.lastLimited()) ++saturated_steps_;
  const double q_after = sim_.state().size() > 2 ? sim_.state()[2] : 0.0;
  // Display only: the pitch angle is not a state of the model; trapezoidal integral of q.
  theta_pitch_ += 0.5 * sim_.dt() * (q_before + q_after);
}

int PlantSimNode::run() {
  ROS_INFO("plant_sim: scenario '%s', %lld steps of %g s (%g s), clock %s%s",
           sim_.scenario().name.c_str(), static_cast<long long>(sim_.totalSteps()), sim_.dt(),
           sim_.scenario().endTime(), clockModeName(params_.clock),
           params_.clock == ClockMode::kRealtime
               ? (", " + std::to_string(params_.rate) + " Hz").c_str()
               : "");
  return params_.clock == ClockMode::kLockstep ? runLockstep() : runRealtime();
}

int PlantSimNode::runLockstep() {
  if (clock_pub_) {
    rosgraph_msgs::Clock c;
    c.clock = simStamp(0.0);
    clock_pub_.publish(c);
  }
  if (!waitForSubscribers()) return kExitRuntimeError;
  // ~cpu_affinity (not ~rt_priority: lockstep has no deadlines): with the controller's thread
  // pinned to the same CPU each hand-off of the round trip is a switch on that CPU, not a
  // wake-up of another (docs/reference/ros.md).
  const SchedulingResult sched = applyRealtimeScheduling(0, params_.cpu_affinity);
  if (!sched.warnings.empty()) ROS_WARN("%s", sched.warnings.c_str());
  scheduling_ = sched.describe();
  wall_start_ = wallNow();
  rosgraph_msgs::Clock clock_msg;
  const auto lag = static_cast<std::uint64_t>(params_.max_recorder_lag);
  const auto clock_every = static_cast<std::uint64_t>(params_.clock_decimation);
  const auto total = static_cast<std::uint64_t>(sim_.totalSteps());
  while (ctx_.ok() && !sim_.done()) {
    const auto k = static_cast<std::uint64_t>(sim_.step());
    // Back-pressure: a recorder that falls too far behind would hold an ever larger backlog
    // in this process, lost if the run ends before it is sent.
    if (!waitForRecorder(k, lag)) {
      finish(false);
      return kExitRuntimeError;
    }
    const ros::Time stamp = simStamp(sim_.time());
    if (clock_pub_ && (k % clock_every == 0 || k + 1 == total)) {
      clock_msg.clock = stamp;
      clock_pub_.publish(clock_msg);
    }
    publishSample(stamp);
    const double deadline = wallNow() + params_.command_timeout;
    double resend_at =
        params_.resend_interval > 0.0 ? wallNow() + params_.resend_interval : deadline;
    double u = 0.0;
    bool answered = false;
    while (ctx_.ok()) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (have_cmd_ && cmd_step_ == k) {
          u = cmd_u_;
          answered = true;
        }
      }
      if (answered) break;
      const double now = wallNow();
      if (now >= deadline) {
        ROS_ERROR(
            "no command for step %llu (t = %.6f s) on %s within %.3f s "
            "(~command_timeout): %s; stopping (exit code %d)",
            static_cast<unsigned long long>(k), sim_.time(), cmd_sub_.getTopic().c_str(),
            params_.command_timeout, noCommandCause("did not answer").c_str(), kExitRuntimeError);
        finish(false);
        return kExitRuntimeError;
      }
      if (now >= resend_at) {
        // The state was lost, or reached the controller before it subscribed (an extra
        // subscriber can make the start-up count look complete). The same message again, and
        // only the state (nothing waits on the truth or tf): the controller ignores a repeat
        // and the recorder does not write it twice.
        ROS_WARN("no command for step %llu after %.3f s: publishing its state again",
                 static_cast<unsigned long long>(k), params_.resend_interval);
        ++resent_;
        state_pub_.publish(last_state_);
        resend_at = now + params_.resend_interval;
      }
      // Blocks until a callback is queued (or the bounded wait ends): no polling delay.
      queue_.callAvailable(ros::WallDuration(std::min(std::min(deadline, resend_at) - now, 0.1)));
    }
    if (!answered) break;  // shutdown requested
    advance(u);
    updater_.update();
  }
  // The bag must hold the last state before this node (and so the run) ends.
  if (sim_.done() && !waitForRecorder(static_cast<std::uint64_t>(sim_.totalSteps() - 1), 0)) {
    finish(false);
    return kExitRuntimeError;
  }
  finish(sim_.done());
  linger();
  return 0;
}

void PlantSimNode::linger() {
  if (!params_.linger || !completed_ || !ctx_.ok()) return;
  // Leave every topic (a run monitor sees the plant go, as if it had exited) but stay alive,
  // so that a launch file can mark this node required without its normal end ending the launch.
  state_pub_.shutdown();
  truth_pub_.shutdown();
  clock_pub_.shutdown();
  tf_pub_.shutdown();
  cmd_sub_.shutdown();
  progress_sub_.shutdown();
  ready_sub_.shutdown();
  ROS_INFO("plant_sim: run complete, topics closed; staying alive until shut down (~linger)");
  while (ctx_.ok()) ros::WallDuration(0.05).sleep();
}

int PlantSimNode::runRealtime() {
  if (!waitForSubscribers()) return kExitRuntimeError;
  // The tick thread (this one): optional SCHED_FIFO priority and CPU affinity; a refusal is a
  // warning and normal scheduling.
  // In a process of its own also roscpp's receiving thread, which reads each command first.
  const SchedulingResult sched =
      applyRealtimeScheduling(params_.rt_priority, params_.cpu_affinity, !ctx_.isNodelet());
  if (!sched.warnings.empty()) ROS_WARN("%s", sched.warnings.c_str());
  scheduling_ = sched.describe();
  // Absolute deadlines (clock_nanosleep TIMER_ABSTIME): a late tick does not shift the later
  // ones, so 60 s of ticks take 60 s.
  TickSource ticks(1.0 / params_.rate);
  wall_start_ = wallNow();
  ticks.start();
  publishSample(ros::Time(ros::WallTime::now().toSec()));
  // A controller that subscribed and then died (or never answers) would leave the plant
  // holding trim through the whole scenario: give up unless one valid command arrives.
  const double first_cmd_deadline =
      params_.start_timeout > 0.0 ? wall_start_ + params_.start_timeout : 0.0;
  while (ctx_.ok()) {
    // This thread takes the commands itself (no spinner thread in between) until the answer
    // to the current step is in or the tick is nearly due (kept 50 us for the wake-up).
    const std::int64_t serve_until = ticks.nextDeadlineNs() - 50000;
    while (ctx_.ok()) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (have_cmd_ && cmd_step_ == static_cast<std::uint64_t>(sim_.step())) break;
      }
      const std::int64_t left = serve_until - monotonicNs();
      if (left <= 0) break;
      queue_.callAvailable(ros::WallDuration(static_cast<double>(left) * 1e-9));
    }
    tick_late_us_.push_back(1e6 * ticks.waitNext());
    // Behind schedule the ticks run back to back until the simulation has caught up.
    if (ticks.late()) ++late_ticks_;
    double u = 0.0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!have_cmd_ && first_cmd_deadline > 0.0 && wallNow() > first_cmd_deadline) {
        ROS_ERROR(
            "no valid command on %s within %.1f s of the first state (~start_timeout): %s; "
            "giving up (exit code %d)",
            cmd_sub_.getTopic().c_str(), params_.start_timeout,
            noCommandCause("does not answer").c_str(), kExitRuntimeError);
        break;
      }
      if (!have_cmd_ || cmd_step_ != static_cast<std::uint64_t>(sim_.step())) ++stale_steps_;
      // Zero-order hold on the latest valid command while it is fresh; without one (none
      // yet, the controller gone, or only rejected ones) hold trim rather than an old u.
      const bool fresh = have_cmd_ && wallNow() - last_cmd_wall_ <= params_.cmd_timeout;
      u = fresh ? cmd_u_ : 0.0;
      if (!fresh) {
        ++trim_steps_;
        if (!in_trim_ && have_cmd_) {
          ++trim_episodes_;
          ROS_WARN("no valid command for %.3f s (~cmd_timeout %.3f s): holding trim (u = 0)",
                   wallNow() - last_cmd_wall_, params_.cmd_timeout);
        }
      } else if (in_trim_) {
        ROS_INFO("commands are back after %lld trim step(s)", static_cast<long long>(trim_steps_));
      }
      in_trim_ = !fresh;
    }
    advance(u);
    updater_.update();
    if (sim_.done()) break;
    const ros::WallTime now = ros::WallTime::now();
    publishSample(ros::Time(now.sec, now.nsec));
  }
  bool gave_up = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    gave_up = !have_cmd_ && ctx_.ok() && !sim_.done();
  }
  finish(sim_.done());
  if (gave_up) return kExitRuntimeError;
  linger();
  return 0;
}

void PlantSimNode::finish(bool completed) {
  wall_end_ = wallNow();
  completed_ = completed;
  if (completed && last_state_) done_pub_.publish(last_state_);
  const RunReport r = report();
  ROS_INFO(
      "plant_sim: %s after %lld of %lld steps in %.3f s wall; commands %lld (ignored %lld); "
      "latency p50 %.1f us, p99 %.1f us, max %.1f us; stale steps %lld, late ticks %lld, "
      "resent states %lld, waits for the recorder %lld",
      completed ? "scenario complete" : "stopped", static_cast<long long>(r.steps),
      static_cast<long long>(r.total_steps), r.wall_time_s,
      static_cast<long long>(r.commands_received), static_cast<long long>(r.commands_ignored),
      r.latency.p50_us, r.latency.p99_us, r.latency.max_us, static_cast<long long>(r.stale_steps),
      static_cast<long long>(r.late_ticks), static_cast<long long>(r.resent_states),
      static_cast<long long>(r.recorder_waits));
  if (cmd_guard_.dropped() > 0)
    ROS_WARN("plant_sim: %lld command(s) from foreign publishers dropped (~accept_from): %s",
             static_cast<long long>(cmd_guard_.dropped()), cmd_guard_.droppedText().c_str());
  if (!params_.latency_report.empty()) {
    std::ofstream f(params_.latency_report);
    f << runReportJson(r) << "\n";
    if (!f) ROS_ERROR("could not write ~latency_report '%s'", params_.latency_report.c_str());
  }
  if (completed && params_.shutdown_grace > 0.0) {
    // Subscribers such as rosbag may still have the last samples in their socket buffers;
    // keep the connections open briefly so nothing is cut off when this node exits.
    const double end = wallNow() + params_.shutdown_grace;
    while (ctx_.ok() && wallNow() < end) queue_.callAvailable(ros::WallDuration(0.01));
  }
}

void PlantSimNode::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(mutex_);
  const double now = wallNow();
  const double step_rate = step_rate_.update(sim_.step(), now);
  const double cmd_rate = cmd_rate_.update(commands_received_, now);
  const double cmd_age = have_cmd_ ? now - last_cmd_wall_ : -1.0;
  if (params_.clock == ClockMode::kRealtime && in_trim_ && have_cmd_) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR,
                 "no valid command within ~cmd_timeout: holding trim");
  } else if (commands_rejected_ > 0) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "non-finite commands rejected");
  } else if (cmd_guard_.dropped() > 0) {
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                 "commands from foreign publishers dropped (~accept_from)");
  } else {
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "running");
  }
  stat.add("clock", clockModeName(params_.clock));
  stat.add("step", sim_.step());
  stat.add("total steps", sim_.totalSteps());
  stat.add("state rate [Hz, wall]", step_rate);
  stat.add("command rate [Hz, wall]", cmd_rate);
  stat.add("commands received", commands_received_);
  stat.add("commands ignored (wrong step)", commands_ignored_);
  stat.add("commands rejected (non-finite)", commands_rejected_);
  stat.add("last rejection", last_rejection_);
  stat.add("stale commands ignored (lockstep)", stale_cmds_ignored_);
  stat.add("command age [s, wall]", cmd_age);
  stat.add("holding trim", params_.clock == ClockMode::kRealtime && in_trim_);
  stat.add("trim steps", trim_steps_);
  stat.add("trim episodes", trim_episodes_);
  stat.add("saturated steps", saturated_steps_);
  stat.add("stale steps", stale_steps_);
  stat.add("late ticks", late_ticks_);
  stat.add("resent states", resent_);
  stat.add("accept from", cmd_guard_.acceptedText());
  stat.add("foreign publisher drops", cmd_guard_.dropped());
  stat.add("foreign publishers", cmd_guard_.droppedText());
}

RunReport PlantSimNode::report() const {
  std::lock_guard<std::mutex> lock(mutex_);
  RunReport r;
  r.clock = clockModeName(params_.clock);
  r.scenario = sim_.scenario().name;
  r.dt = sim_.dt();
  r.rate_hz = params_.clock == ClockMode::kRealtime ? params_.rate : 0.0;
  r.steps = sim_.step();
  r.total_steps = sim_.totalSteps();
  r.completed = completed_;
  r.wall_time_s = (wall_end_ > 0.0 ? wall_end_ : wallNow()) - wall_start_;
  r.commands_received = commands_received_;
  r.commands_ignored = commands_ignored_;
  r.stale_steps = stale_steps_;
  r.late_ticks = late_ticks_;
  r.resent_states = resent_;
  r.recorder_waits = recorder_waits_;
  r.latency = summarizeLatency(latency_us_);
  r.scheduling = scheduling_;
  r.tick_late = summarizeLatency(tick_late_us_);
  return r;
}

int runPlantSimNode() {
  const NodeContext ctx = NodeContext::forProcess();
  PlantNodeParams params;
  if (!readNodeParams(ctx, readPlantNodeParams, &params)) return processExitCode();
  PlantSimNode node(ctx, params);
  const int code = node.run();
  if (code != 0) return code;
  // A normal end: under roslaunch, end the launch quietly and wait to be stopped with it
  // (returning now would race roslaunch into reporting this process as died).
  requestProcessExit(0);
  while (ros::ok()) ros::WallDuration(0.05).sleep();
  return processExitCode();
}

}  // namespace ros1
}  // namespace preadaptive_mrac
