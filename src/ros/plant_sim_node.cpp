#include "preadaptive_mrac/ros/plant_sim_node.hpp"

#include <geometry_msgs/TransformStamped.h>
#include <ros/callback_queue.h>
#include <std_msgs/Bool.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <boost/make_shared.hpp>
#include <cmath>
#include <fstream>

#include "preadaptive_mrac/jsbsim/jsbsim_process.hpp"
#include "preadaptive_mrac/ros/ros_params.hpp"
#include "preadaptive_mrac/ros/tick_source.hpp"

namespace preadaptive_mrac {
namespace ros1 {
namespace {

constexpr uint32_t kCommandQueue = 100;

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
      own_(nh_),
      params_(params),
      sim_(params.run.plant, params.run.scenario, params.dt),
      updater_(ros::NodeHandle(), ctx.pnh(), ctx.name()),
      cmd_guard_(makePublisherGuard(ctx, params.accept_from)) {
  // The plant's own subscriptions go to a queue that only its loop serves: in lockstep the
  // loop takes each command as soon as it is queued, with no other thread in between, in a
  // process of its own and in a shared nodelet manager alike.
  own_.setCallbackQueue(&queue_);
  updater_.setHardwareID("plant_sim");
  updater_.add("plant", this, &PlantSimNode::diagnose);
  // ~queue_size bounds the backlog kept for each slow subscriber (a recorder under load falls
  // seconds behind a lockstep run); 0 keeps everything, so no sample is lost.
  const auto q = static_cast<uint32_t>(params_.queue_size);
  state_pub_ = nh_.advertise<PlantState>("plant/state", q);
  truth_pub_ = nh_.advertise<PlantTruth>("plant/truth", q);
  done_pub_ = nh_.advertise<PlantState>("plant/done", 1, /*latch=*/true);
  clock_ = makePlantClock(*this);
  tf_pub_ = nh_.advertise<tf2_msgs::TFMessage>("tf", 100);
  cmd_sub_ =
      own_.subscribe("controller/elevator_cmd", kCommandQueue, &PlantSimNode::commandCallback, this,
                     ros::TransportHints().tcpNoDelay());
  cmd_topic_ = cmd_sub_.getTopic();
  if (cmd_guard_.enabled())
    ROS_INFO("taking commands on %s only from %s (~accept_from)", cmd_topic_.c_str(),
             cmd_guard_.acceptedText().c_str());
  if (!params_.recorder_progress_topic.empty()) {
    // Realtime only waits for the recorder to exist before step 0 (waitForSubscribers).
    progress_sub_ = own_.subscribe<RecorderProgress>(
        params_.recorder_progress_topic, 100,
        [this](const RecorderProgress::ConstPtr& m) {
          // this plant's states and commands, not another plant's
          if (m->topic == state_pub_.getTopic() || m->topic == cmd_topic_) clock_->progress(*m);
        },
        ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
    // The recorder's ~connections is beside its ~progress (both private topics of that node).
    connections_sub_ = own_.subscribe<RecorderConnections>(
        ros::names::parentNamespace(progress_sub_.getTopic()) + "/connections", 1,
        [this](const RecorderConnections::ConstPtr& m) {
          recorder_records_commands_ = false;
          for (std::size_t i = 0; i < m->topics.size() && i < m->publishers.size(); ++i) {
            if (m->topics[i] != cmd_topic_) continue;
            recorder_records_commands_ = true;
            recorder_cmd_publishers_ = static_cast<int>(m->publishers[i]);
          }
        });
  }
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
  double latency_us = 0.0;
  if (!clock_->take(*msg, arrival, &latency_us)) return;
  latency_us_.add(latency_us);
  ++commands_received_;
  have_cmd_ = true;
  cmd_step_ = msg->step;
  cmd_u_ = msg->u;
  cmd_stale_ = msg->stale;
  last_cmd_wall_ = arrival;
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
        (!ready_sub_ || controller_ready_) && recorderHasTheCommands())
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
    // take controller/ready and the recorder's connections, which come on this node's own
    // queue).
    if (ready_sub_ || connections_sub_)
      queue_.callAvailable(ros::WallDuration(0.002));
    else
      ros::WallDuration(0.002).sleep();
  }
  return false;
}

bool PlantSimNode::recorderHasTheCommands() const {
  if (!connections_sub_ || !recorder_records_commands_) return true;
  return recorder_cmd_publishers_ >= 0 &&
         recorder_cmd_publishers_ >= static_cast<int>(cmd_sub_.getNumPublishers());
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
  if (!recorderHasTheCommands())
    s += "; the recorder is connected to " + std::to_string(std::max(recorder_cmd_publishers_, 0)) +
         " of the " + std::to_string(cmd_sub_.getNumPublishers()) + " publisher(s) of " +
         cmd_topic_ +
         (recorder_cmd_publishers_ < 0
              ? " (it has not said so on " + connections_sub_.getTopic() + ")"
              : std::string());
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
  truth->condition_names.reserve(kPlantConditionTable.size());
  truth->conditions.reserve(kPlantConditionTable.size());
  truth->condition_of_previous_step.reserve(kPlantConditionTable.size());
  // The plant's rows always, the engine's too on an engine.
  const ConditionRows rows{true, sim_.engine() != nullptr};
  for (const PlantConditionColumn& c : kPlantConditionTable) {
    if (!rows.has(c)) continue;
    truth->condition_names.emplace_back(c.name);
    truth->conditions.push_back(sim_.conditions().*c.field);
    truth->condition_of_previous_step.push_back(c.known == ConditionKnown::kAfterStep ? 1 : 0);
  }
  const EnvelopeExit& exit = sim_.envelopeExit();
  truth->envelope_bound = exit.exited ? exit.bound : "";
  truth->envelope_exit_t = exit.exited ? exit.t : -1.0;
  if (exit.exited) truth->envelope_exit = exit.describe();
  truth_pub_.publish(PlantTruth::ConstPtr(truth));

  // The pitch, display only: an engine knows its pitch attitude. The linear model has no
  // flight path (it holds the speed, and a steady alpha above trim is a steady pull-up: the
  // integral of q would loop the aircraft), so its pitch is drawn on a level flight path:
  // theta = alpha.
  const FlightOutputs* f = sim_.flight();
  const double pitch = f ? f->pitch : sim_.state()[out];
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
  state->theta_pitch = pitch;
  state->r = sim_.reference();
  state->elevator = applied_u_;
  state->elevator_command = sim_.lastCommand();
  clock_->published(k, wallNow());
  last_state_ = state;
  state_pub_.publish(last_state_);

  if (k % static_cast<std::uint64_t>(params_.tf_decimation) == 0) {
    const auto tfs = boost::make_shared<tf2_msgs::TFMessage>();
    tfs->transforms.push_back(
        pitchTransform(stamp, params_.world_frame, params_.body_frame, -pitch));
    // The velocity vector lies alpha below the nose: rotate the body frame nose-down by alpha
    // (on an engine the whole angle, pitch attitude - flight path angle, trim included).
    tfs->transforms.push_back(pitchTransform(stamp, params_.body_frame, params_.velocity_frame,
                                             f ? f->pitch - f->flight_path : x[out]));
    tf_pub_.publish(tf2_msgs::TFMessage::ConstPtr(tfs));
  }
}

void PlantSimNode::advance(double u) {
  sim_.advance(u);
  // After the actuator limits of plant.actuator (u itself when they are off).
  applied_u_ = sim_.lastApplied();
  // What the limits did, not applied != commanded: with a servo delay or lag the deflection
  // differs from the command in nearly every step without any limit being reached.
  if (sim_.lastLimited()) ++saturated_steps_;
  if (sim_.envelopeExit().exited && !envelope_logged_) {
    envelope_logged_ = true;
    ROS_ERROR("plant_sim: left the flight envelope at %s%s", sim_.envelopeExit().describe().c_str(),
              sim_.nonFinite() ? "; the state is not finite: the run ends" : "");
    // At once, not at the updater's next period: a run whose state is no longer finite ends
    // within this step, and its diagnostics would otherwise never say why.
    updater_.force_update();
  }
}

int PlantSimNode::run() {
  ROS_INFO("plant_sim: scenario '%s', %lld steps of %g s (%g s), clock %s%s",
           sim_.scenario().name.c_str(), static_cast<long long>(sim_.totalSteps()), sim_.dt(),
           sim_.scenario().endTime(), clockModeName(params_.clock),
           params_.clock == ClockMode::kRealtime
               ? (", " + std::to_string(params_.rate) + " Hz").c_str()
               : "");
  try {
    const int code = clock_->run();
    sim_.closeEngine();  // no JSBSim outlives its run (a lingering node, a loaded nodelet)
    return code;
  } catch (const JsbsimError& e) {
    // The engine failed mid-run (its process died or stopped answering): the run ends here,
    // saying so; the engine's process is already stopped (JsbsimProcess's error paths).
    ROS_ERROR("plant_sim: the run ends at step %lld of %lld (t = %g s): %s (exit code %d)",
              static_cast<long long>(sim_.step()), static_cast<long long>(sim_.totalSteps()),
              sim_.time(), e.what(), kExitRuntimeError);
    finish(false);
    return kExitRuntimeError;
  }
}

void PlantSimNode::linger() {
  if (!params_.linger || !completed_ || !ctx_.ok()) return;
  sim_.closeEngine();  // its JSBSim ends with the run, not with the node
  // Leave every topic (a run monitor sees the plant go, as if it had exited) but stay alive,
  // so that a launch file can mark this node required without its normal end ending the launch.
  state_pub_.shutdown();
  truth_pub_.shutdown();
  clock_->close();
  tf_pub_.shutdown();
  cmd_sub_.shutdown();
  progress_sub_.shutdown();
  ready_sub_.shutdown();
  ROS_INFO("plant_sim: run complete, topics closed; staying alive until shut down (~linger)");
  while (ctx_.ok()) ros::WallDuration(0.05).sleep();
}

void PlantSimNode::schedule(int rt_priority, bool receiving_thread) {
  const SchedulingResult sched =
      applyRealtimeScheduling(rt_priority, params_.cpu_affinity, receiving_thread);
  if (!sched.warnings.empty()) ROS_WARN("%s", sched.warnings.c_str());
  scheduling_ = sched.describe();
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
  NodeStatus status(stat);
  status.problem(sim_.envelopeExit().exited, diagnostic_msgs::DiagnosticStatus::ERROR,
                 "left the flight envelope at " + sim_.envelopeExit().describe());
  clock_->problems(status);
  status
      .problem(commands_rejected_ > 0, diagnostic_msgs::DiagnosticStatus::WARN,
               "non-finite commands rejected")
      .problem(cmd_guard_.dropped() > 0, diagnostic_msgs::DiagnosticStatus::WARN,
               "commands from foreign publishers dropped (~accept_from)")
      .summarize("running")
      .rows({{"clock", clockModeName(params_.clock)},
             {"step", sim_.step()},
             {"total steps", sim_.totalSteps()},
             {"state rate [Hz, wall]", step_rate_.update(sim_.step(), now)},
             {"command rate [Hz, wall]", cmd_rate_.update(commands_received_, now)},
             {"commands received", commands_received_},
             {"commands ignored (wrong step)", commands_ignored_},
             {"commands rejected (non-finite)", commands_rejected_},
             {"last rejection", last_rejection_},
             {"command age [s, wall]", have_cmd_ ? now - last_cmd_wall_ : -1.0},
             {"saturated steps", saturated_steps_},
             {"envelope exit", sim_.envelopeExit().describe()}});
  clock_->rows(status);
  status.guard(cmd_guard_);
}

RunReport PlantSimNode::report() const {
  std::lock_guard<std::mutex> lock(mutex_);
  RunReport r;
  r.clock = clockModeName(params_.clock);
  r.scenario = sim_.scenario().name;
  r.dt = sim_.dt();
  r.steps = sim_.step();
  r.total_steps = sim_.totalSteps();
  r.completed = completed_;
  r.wall_time_s = (wall_end_ > 0.0 ? wall_end_ : wallNow()) - wall_start_;
  r.commands_received = commands_received_;
  r.commands_ignored = commands_ignored_;
  r.latency = latency_us_.summary();
  r.scheduling = scheduling_;
  clock_->report(&r);
  return r;
}

std::unique_ptr<PlantSimNode> makePlantSimNode(const NodeContext& ctx,
                                               const PlantNodeParams& params) {
  for (const std::string& d : params.run.derived) ROS_INFO("derived at start: %s", d.c_str());
  try {
    return std::make_unique<PlantSimNode>(ctx, params);
  } catch (const JsbsimError& e) {
    // plant.engine jsbsim that cannot start (not installed, an aircraft that does not load,
    // a failed trim): what is wrong and how to fix it, before anything is advertised.
    ROS_FATAL("%s: the plant's engine cannot start: %s (exit code %d)", ctx.name().c_str(),
              e.what(), kExitConfigError);
    ctx.end(kExitConfigError);
    return nullptr;
  }
}

int runPlantSimNode() {
  const NodeContext ctx = NodeContext::forProcess();
  PlantNodeParams params;
  if (!readNodeParams(ctx, readPlantNodeParams, &params)) return processExitCode();
  std::unique_ptr<PlantSimNode> node = makePlantSimNode(ctx, params);
  if (!node) return processExitCode();
  const int code = node->run();
  if (code != 0) return code;
  // A normal end: under roslaunch, end the launch quietly and wait to be stopped with it
  // (returning now would race roslaunch into reporting this process as died).
  requestProcessExit(0);
  while (ros::ok()) ros::WallDuration(0.05).sleep();
  return processExitCode();
}

}  // namespace ros1
}  // namespace preadaptive_mrac
