#include "preadaptive_mrac/ros/mrac_controller_node.hpp"

#include <algorithm>
#include <boost/make_shared.hpp>
#include <cmath>
#include <cstdio>
#include <memory>

#include "preadaptive_mrac/io/weights_io.hpp"
#include "preadaptive_mrac/ros/controller_reconfigure.hpp"
#include "preadaptive_mrac/ros/node_status.hpp"
#include "preadaptive_mrac/ros/ros_params.hpp"
#include "preadaptive_mrac/ros/tick_source.hpp"

namespace preadaptive_mrac {
namespace ros1 {
namespace {

constexpr uint32_t kSampleQueue = 10000;  // incoming states

}  // namespace

MracControllerNode::MracControllerNode(const NodeContext& ctx, const ControllerNodeParams& params)
    : ctx_(ctx),
      nh_(ctx.nh()),
      params_(params),
      ctl_(designModelOf(params.run.plant, params.run.controller), params.run.controller),
      // The sequencer's guard rejects malformed samples before they reach the controller and,
      // fed the staleness clock, tells when the last valid one is older than ~stale_timeout.
      seq_(&ctl_, params.run.plant.n(), params.run.controller.sample_time, params.stale_timeout,
           params.stale_policy),
      updater_(ros::NodeHandle(), ctx.pnh(), ctx.name()),
      input_guard_(makePublisherGuard(ctx, params.accept_from)),
      truth_guard_(static_cast<std::size_t>(params.run.plant.n()), 1e300),
      plant_silence_(0.25 * static_cast<double>(params.plant_lost_samples) *
                     params.run.controller.sample_time) {
  const int n = params_.run.plant.n();
  if (!params_.weights_in.empty()) {
    ctl_.setNetwork(loadWeights(params_.weights_in, ctl_.config().hidden, n));
    ROS_INFO("loaded network weights from %s (%lld episodes learned before)",
             params_.weights_in.c_str(), static_cast<long long>(ctl_.network().state().episodes));
  }
  episodes_saved_ = ctl_.network().state().episodes;
  // ~queue_size bounds the backlog kept for each slow subscriber; 0 keeps everything.
  const auto q = static_cast<uint32_t>(params_.queue_size);
  cmd_pub_ = nh_.advertise<ElevatorCommand>("controller/elevator_cmd", q);
  attention_pub_ = nh_.advertise<AttentionEvent>("controller/attention", q);
  status_pub_ = nh_.advertise<AdaptationStatus>("controller/status", q);
  // Latched true once this node takes states (a lockstep plant with ~wait_for_controller
  // waits for it before step 0).
  ready_pub_ = nh_.advertise<std_msgs::Bool>("controller/ready", 1, /*latch=*/true);
  updater_.setHardwareID("mrac_controller");
  updater_.add("controller", this, &MracControllerNode::diagnose);
  reconf_ = std::make_unique<ControllerReconfigure>(nh_, ros::NodeHandle(ctx.pnh(), "reconfigure"),
                                                    &ctl_, ctx.keyStyle());
}

MracControllerNode::~MracControllerNode() = default;

void MracControllerNode::fatal(const std::string& what) {
  ROS_FATAL("%s", what.c_str());
  failed_ = true;
  ctx_.end(kExitConfigError);
}

bool MracControllerNode::subscribersReady() const {
  return static_cast<int>(cmd_pub_.getNumSubscribers()) >= params_.min_command_subscribers &&
         static_cast<int>(status_pub_.getNumSubscribers()) >= params_.min_status_subscribers &&
         static_cast<int>(attention_pub_.getNumSubscribers()) >= params_.min_status_subscribers;
}

void MracControllerNode::start() {
  const ControllerDesign& d = ctl_.design();
  ROS_INFO("mrac_controller: mode %s, K = [%g %g %g], CARE residual %.2e, Lyapunov residual %.2e",
           ctl_.mode().c_str(), d.K.size() > 0 ? d.K[0] : 0.0, d.K.size() > 1 ? d.K[1] : 0.0,
           d.K.size() > 2 ? d.K[2] : 0.0, d.care_residual, d.lyapunov_residual);
  // Only take states once every wanted subscriber (the plant, a recorder) is connected, so
  // that nothing this node publishes is lost to a late connection. Connections are made by
  // roscpp's own threads: poll them from a timer, so nothing blocks (a nodelet's callbacks
  // share the manager's threads).
  start_wall_ = ros::WallTime::now().toSec();
  start_timer_ = nh_.createWallTimer(ros::WallDuration(0.002), [this](const ros::WallTimerEvent&) {
    if (subscribersReady()) {
      start_timer_.stop();
      subscribe();
      return;
    }
    const double timeout = params_.start_timeout;
    if (timeout > 0.0 && ros::WallTime::now().toSec() - start_wall_ > timeout) {
      start_timer_.stop();
      ROS_ERROR(
          "no plant after %.1f s (~start_timeout): %u subscriber(s) on %s (wanted %d, "
          "~min_command_subscribers: the plant and recorders), %u on %s and %u on %s (wanted "
          "%d, ~min_status_subscribers); a plant that refuses its parameters exits with code 2 "
          "naming each key (see its output); giving up (exit code %d)",
          timeout, cmd_pub_.getNumSubscribers(), cmd_pub_.getTopic().c_str(),
          params_.min_command_subscribers, status_pub_.getNumSubscribers(),
          status_pub_.getTopic().c_str(), attention_pub_.getNumSubscribers(),
          attention_pub_.getTopic().c_str(), params_.min_status_subscribers, kExitRuntimeError);
      failed_ = true;
      ctx_.end(kExitRuntimeError);
    }
  });
}

void MracControllerNode::subscribe() {
  state_sub_ = nh_.subscribe("plant/state", kSampleQueue, &MracControllerNode::stateCallback, this,
                             ros::TransportHints().tcpNoDelay());
  state_topic_ = state_sub_.getTopic();
  if (ctl_.needsTruth()) {
    truth_sub_ = nh_.subscribe("plant/truth", kSampleQueue, &MracControllerNode::truthCallback,
                               this, ros::TransportHints().tcpNoDelay());
    truth_topic_ = truth_sub_.getTopic();
    ROS_WARN(
        "mode %s uses the SIMULATION TRUTH theta from %s (%s; only a simulator has it); "
        "each state waits for the truth of the same step",
        ctl_.mode().c_str(), truth_sub_.getTopic().c_str(), ctl_.truthUse().c_str());
  }
  if (input_guard_.enabled())
    ROS_INFO("taking %s%s only from %s (~accept_from)", state_topic_.c_str(),
             truth_sub_ ? (" and " + truth_topic_).c_str() : "",
             input_guard_.acceptedText().c_str());
  stale_timer_ = nh_.createTimer(ros::Duration(params_.run.controller.sample_time),
                                 &MracControllerNode::staleTimerCallback, this);
  const auto ready = boost::make_shared<std_msgs::Bool>();
  ready->data = true;
  ready_pub_.publish(std_msgs::Bool::ConstPtr(ready));
}

void MracControllerNode::finish() {
  if (finished_) return;
  finished_ = true;
  start_timer_.stop();
  stale_timer_.stop();
  state_sub_.shutdown();
  truth_sub_.shutdown();
  if (!failed_) saveWeights("shutdown", true);
  ctx_.printFinal(std::to_string(seq_.steps()) + " steps, " + std::to_string(seq_.gaps()) +
                  " gap(s) in the state sequence, " +
                  std::to_string(ctl_.network().state().episodes) + " learning episode(s)");
  if (input_guard_.dropped() > 0)
    ctx_.printFinal(std::to_string(input_guard_.dropped()) +
                    " message(s) from foreign publishers dropped (~accept_from): " +
                    input_guard_.droppedText());
}

void MracControllerNode::saveWeights(const char* why, bool at_end) {
  if (params_.weights_out.empty()) return;
  const bool after_shutdown = at_end || !ros::ok();
  try {
    preadaptive_mrac::saveWeights(params_.weights_out, ctl_.network().state());
    episodes_saved_ = ctl_.network().state().episodes;
    const std::string line = "saved network weights (" + std::to_string(episodes_saved_) +
                             " episodes) to " + params_.weights_out + " (" + why + ")";
    if (after_shutdown) {
      ctx_.printFinal(line);
    } else {
      ROS_INFO("%s", line.c_str());
    }
  } catch (const std::exception& e) {
    const std::string line =
        "could not save network weights to " + params_.weights_out + ": " + e.what();
    if (after_shutdown) {
      ctx_.printFinal(line, true);
    } else {
      ROS_ERROR("%s", line.c_str());
    }
  }
}

void MracControllerNode::stateCallback(const ros::MessageEvent<PlantState const>& event) {
  if (failed_) return;
  // ~accept_from: a state from another node is dropped before anything else: it is not
  // answered, not counted as received and does not refresh the staleness timer.
  if (!input_guard_.admitEvent(event, state_topic_)) return;
  const PlantState::ConstPtr msg = event.getConstMessage();
  if (params_.rt_priority > 0 || params_.cpu_affinity >= 0) {
    // The thread that runs this callback (the process's spinner, or the nodelet's own
    // thread: src/ros/nodelets.cpp) gets ~rt_priority / ~cpu_affinity, once.
    thread_local bool scheduled = false;
    if (!scheduled) {
      scheduled = true;
      // In a process of its own also roscpp's receiving thread, which reads each state first.
      const SchedulingResult r =
          applyRealtimeScheduling(params_.rt_priority, params_.cpu_affinity, !ctx_.isNodelet());
      if (!r.warnings.empty()) {
        ROS_WARN("%s", r.warnings.c_str());
      } else {
        ROS_INFO("state callback thread: %s", r.describe().c_str());
      }
    }
  }
  ++states_received_;
  plant_silence_.heard(ros::Time::now().toSec());
  latest_stamp_ = std::max(latest_stamp_, msg->header.stamp.toSec());
  if (!ctl_.needsTruth()) {
    process(*msg, nullptr);
    return;
  }
  pending_.push_back(msg);
  if (static_cast<int>(pending_.size()) > params_.truth_buffer) {
    ROS_ERROR_THROTTLE(1.0,
                       "%zu states waiting for their truth on %s (~truth_buffer %d); "
                       "dropping step %llu",
                       pending_.size(), truth_sub_.getTopic().c_str(), params_.truth_buffer,
                       static_cast<unsigned long long>(pending_.front()->step));
    pending_.pop_front();
  }
  drainPending();
}

void MracControllerNode::truthCallback(const ros::MessageEvent<PlantTruth const>& event) {
  if (failed_) return;
  if (!input_guard_.admitEvent(event, truth_topic_)) return;
  const PlantTruth::ConstPtr msg = event.getConstMessage();
  const int n = params_.run.plant.n();
  std::string why;
  if (!truth_guard_.accept(0.0, msg->theta.data(), msg->theta.size(), &why, "theta")) {
    ROS_ERROR_THROTTLE(1.0, "truth for step %llu rejected: %s",
                       static_cast<unsigned long long>(msg->step), why.c_str());
    return;
  }
  Vec theta(n);
  for (int i = 0; i < n; ++i) theta[i] = msg->theta[static_cast<size_t>(i)];
  truth_[msg->step] = theta;
  have_truth_ = true;
  last_truth_step_ = std::max(last_truth_step_, msg->step);
  while (static_cast<int>(truth_.size()) > params_.truth_buffer) truth_.erase(truth_.begin());
  drainPending();
}

void MracControllerNode::drainPending() {
  while (!pending_.empty() && !failed_) {
    const PlantState::ConstPtr& s = pending_.front();
    auto it = truth_.find(s->step);
    if (it != truth_.end()) {
      const Vec theta = it->second;
      // Truth of this and earlier steps is no longer needed.
      truth_.erase(truth_.begin(), std::next(it));
      const PlantState::ConstPtr keep = s;
      pending_.pop_front();
      process(*keep, &theta);
    } else if (have_truth_ && last_truth_step_ > s->step) {
      // Truth arrives in order on one topic: a later step means this one was lost (or was
      // rejected). Answer the state safely rather than leave the plant waiting.
      const PlantState::ConstPtr keep = s;
      pending_.pop_front();
      answerRejected(*keep, "no valid truth arrived for its step");
    } else {
      break;
    }
  }
}

void MracControllerNode::process(const PlantState& msg, const Vec* theta) {
  PlantSample sample;
  sample.step = msg.step;
  sample.t = msg.t;
  sample.dt = msg.dt;
  sample.x = msg.x.data();
  sample.size = msg.x.size();
  sample.r = msg.r;
  sample.elevator = msg.elevator;
  sample.total_steps = msg.total_steps;
  // The time a valid state refreshes the staleness timer with. In lockstep (and under
  // /use_sim_time) the state's own stamp (its sample time): a /clock arrives on another
  // connection and can lag the states (measured: 64 ms in a loaded lockstep pa_learn_exact
  // run, which made the timer fire between two states). On the wall clock, the time of receipt.
  const double now = staleNow();
  const double refresh = params_.clock == ClockMode::kLockstep || ros::Time::isSimTime()
                             ? msg.header.stamp.toSec()
                             : now;
  SampleOutcome o = seq_.onSample(sample, theta, refresh, now);
  switch (o.kind) {
    case SampleOutcome::Kind::kBadSampleTime: {
      const double ts = params_.run.controller.sample_time;
      fatal(ctx_.keyStyle().root + "controller/sample_time: " + std::to_string(ts) +
            " s differs from the plant's step " + std::to_string(msg.dt) + " s on " +
            state_sub_.getTopic() + "; they must be equal");
      return;
    }
    case SampleOutcome::Kind::kRepeated:
      // The plant repeats a state when it got no answer: our command was lost. Answer again
      // (the same command; the controller does not step twice).
      ROS_WARN("state for step %llu repeated: publishing its command again",
               static_cast<unsigned long long>(msg.step));
      if (last_cmd_) cmd_pub_.publish(last_cmd_);
      return;
    case SampleOutcome::Kind::kRejected:
      logSequence(msg, o);
      answerRejected(msg, o.why);
      return;
    case SampleOutcome::Kind::kStepFailed:
      logSequence(msg, o);
      fatal(std::string("controller step ") + std::to_string(msg.step) + " failed: " + o.why);
      return;
    case SampleOutcome::Kind::kStepped:
      logSequence(msg, o);
      publishStep(msg, &o.out);
      return;
  }
}

void MracControllerNode::logSequence(const PlantState& msg, const SampleOutcome& o) {
  if (o.restarted_after)
    // One publisher's states arrive in order, so a step going back means a new plant run.
    ROS_WARN("the plant restarted (step %llu after step %llu): controller reset",
             static_cast<unsigned long long>(msg.step),
             static_cast<unsigned long long>(*o.restarted_after));
  if (o.missing)
    ROS_WARN_THROTTLE(1.0, "states %llu .. %llu never arrived",
                      static_cast<unsigned long long>(o.missing->first),
                      static_cast<unsigned long long>(o.missing->second));
  if (o.finished)
    ROS_INFO("the plant's last step (%llu) answered: the run has finished",
             static_cast<unsigned long long>(msg.step));
  if (o.stale_for) {
    ROS_INFO("valid state again (step %llu) after %.3f s stale: adapting again",
             static_cast<unsigned long long>(msg.step), *o.stale_for);
    updater_.force_update();
  }
}

void MracControllerNode::publishStep(const PlantState& msg, StepOutput* out) {
  const int n = params_.run.plant.n();
  reconf_->recover(out, seq_.x(), msg.step, msg.t);  // never a NaN command: the baseline instead

  // The command first: the plant waits for it. Messages are built once and never touched
  // after publishing (a nodelet in the same process gets the pointer).
  const auto cmd = boost::make_shared<ElevatorCommand>();
  cmd->header.stamp = msg.header.stamp;
  cmd->step = msg.step;
  cmd->t = msg.t;
  cmd->u = out->u;
  cmd->u_baseline = out->u_baseline;
  cmd->u_adaptive = out->u_adaptive;
  cmd->safe = false;
  cmd->stale = false;
  last_cmd_ = cmd;
  cmd_pub_.publish(last_cmd_);
  reconf_->afterStep(*out, msg.step, msg.t, msg.header.stamp);

  if (out->saturated) ++saturated_;
  if (out->event) publishEvent(msg, *out->event);

  const int oi = params_.run.plant.output_index;
  const auto status = boost::make_shared<AdaptationStatus>();
  status->header.stamp = msg.header.stamp;
  status->step = msg.step;
  status->t = msg.t;
  status->mode = ctl_.mode().c_str();
  status->x_ref.assign(out->x_ref.data(), out->x_ref.data() + n);
  status->theta_hat.assign(out->theta_hat.data(), out->theta_hat.data() + n);
  status->alpha_ref = out->x_ref[oi];
  status->e = out->e;
  status->e_dot_est = out->e_dot;
  status->theta_hat_0 = n > 0 ? out->theta_hat[0] : 0.0;
  status->theta_hat_1 = n > 1 ? out->theta_hat[1] : 0.0;
  status->theta_hat_2 = n > 2 ? out->theta_hat[2] : 0.0;
  status->phase_active = ctl_.phaseActive();
  status->episodes = ctl_.network().state().episodes;
  status_pub_.publish(AdaptationStatus::ConstPtr(status));

  if (out->event && out->event->learned && params_.save_every_episode)
    saveWeights("after a learning episode");
  else if (out->event && out->event->type == Event::Type::kRecovered && ctl_.keepsAtRecovery() &&
           params_.save_every_episode)
    saveWeights(("after a recovery (mode " + ctl_.mode() + " keeps what it learned)").c_str());
}

void MracControllerNode::publishEvent(const PlantState& msg, const Event& e) {
  if (e.type == Event::Type::kOnset) ++onsets_;
  if (e.type == Event::Type::kRecovered) ++recoveries_;
  if (e.reset) ++resets_;
  if (e.type == Event::Type::kDecision) ++decision_events_;
  const auto event = boost::make_shared<AttentionEvent>();
  event->header.stamp = msg.header.stamp;
  toMsg(e, msg.step, event.get());
  attention_pub_.publish(AttentionEvent::ConstPtr(event));
  if (e.decision == Event::Decision::kNone) {
    logged_choice_.clear();
    ROS_INFO("t = %.3f s: %s (e = %.5f rad, e_dot = %.5f rad/s%s)", e.t, eventTypeName(e.type), e.e,
             e.e_dot, e.learned ? ", network updated" : "");
    return;
  }
  ++decisions_[static_cast<int>(e.decision)];
  char buf[160];
  std::snprintf(buf, sizeof(buf), "%s at t = %.3f s (score %.3g rad, keeping %.3g rad)",
                event->decision.c_str(), e.t, e.score, e.score_keep);
  last_decision_ = buf;
  const std::string which = e.decision == Event::Decision::kMemory
                                ? event->decision + " #" + std::to_string(e.chosen)
                                : event->decision;
  char line[256];
  std::snprintf(line, sizeof(line),
                "t = %.3f s: %s (e = %.5f rad, e_dot = %.5f rad/s): %s of %d candidates, "
                "residual %.3g rad against %.3g rad keeping",
                e.t, eventTypeName(e.type), e.e, e.e_dot, which.c_str(), e.candidates, e.score,
                e.score_keep);
  // pa_robust re-verifies every few ms inside a phase (dozens of DECISION events per
  // switch): INFO when the choice is new in the phase, the same choice again is DEBUG.
  const bool repeated = e.type == Event::Type::kDecision && which == logged_choice_;
  logged_choice_ = which;
  if (repeated)
    ROS_DEBUG("%s", line);
  else
    ROS_INFO("%s", line);
}

void MracControllerNode::answerRejected(const PlantState& msg, const std::string& why) {
  ROS_ERROR_THROTTLE(1.0,
                     "state for step %llu rejected (%s; %llu so far): answering with the "
                     "%s command of the last valid state",
                     static_cast<unsigned long long>(msg.step), why.c_str(),
                     static_cast<unsigned long long>(seq_.guard().rejected()),
                     params_.stale_policy == StalePolicy::kZero ? "zero" : "baseline");
  // The plant still gets an answer for this step (lockstep would otherwise wait), but the
  // adaptive law, attention and learning do not see the sample.
  last_cmd_ = safeCommand(msg.header.stamp, msg.step, msg.t, false);
  cmd_pub_.publish(last_cmd_);
  ++rejected_answers_;
}

ElevatorCommand::ConstPtr MracControllerNode::safeCommand(const ros::Time& stamp,
                                                          std::uint64_t step, double t,
                                                          bool stale) {
  const double u = seq_.safeCommand();
  const auto c = boost::make_shared<ElevatorCommand>();
  c->header.stamp = stamp;
  c->step = step;
  c->t = t;
  c->u = u;
  c->u_baseline = u;
  c->u_adaptive = 0.0;
  c->safe = true;
  c->stale = stale;
  return c;
}

double MracControllerNode::staleNow() const {
  return params_.clock == ClockMode::kLockstep ? latest_stamp_ : ros::Time::now().toSec();
}

bool MracControllerNode::plantLost() {
  if (params_.clock != ClockMode::kRealtime || params_.plant_lost_samples <= 0 ||
      states_received_ == 0 || seq_.runOver())
    return false;
  const double timeout =
      static_cast<double>(params_.plant_lost_samples) * params_.run.controller.sample_time;
  const double silent = plant_silence_.silentFor(ros::Time::now().toSec());
  if (silent <= timeout) return false;
  // The plant has gone (killed, crashed, unloaded): commands to no plant would only fill a
  // recorder, and a launch that waits on this node would never end.
  ROS_ERROR(
      "no state from the plant on %s for %.3f s (~plant_lost_samples %d x %g s): the plant has "
      "gone (its last state: step %llu); commands stopped, ending (exit code %d)",
      state_topic_.c_str(), silent, params_.plant_lost_samples, params_.run.controller.sample_time,
      static_cast<unsigned long long>(seq_.lastStep()), kExitRuntimeError);
  stale_timer_.stop();
  ctx_.end(kExitRuntimeError);
  return true;
}

void MracControllerNode::staleTimerCallback(const ros::TimerEvent&) {
  if (failed_ || plantLost()) return;
  const double now = staleNow();
  if (const std::optional<StaleTick> tick = seq_.onTimer(now)) {
    if (tick->began) {
      const InputGuard& guard = seq_.guard();
      ROS_WARN(
          "no valid state on %s for %.3f s (~stale_timeout %.3f s; %llu rejected so far): "
          "publishing the %s command of step %llu, adaptation frozen",
          state_sub_.getTopic().c_str(), guard.age(now), params_.stale_timeout,
          static_cast<unsigned long long>(guard.rejected()),
          params_.stale_policy == StalePolicy::kZero ? "zero" : "baseline",
          static_cast<unsigned long long>(seq_.lastValidStep()));
      updater_.force_update();
    }
    const ros::Time stamp =
        params_.clock == ClockMode::kLockstep ? ros::Time(tick->t) : ros::Time::now();
    cmd_pub_.publish(safeCommand(stamp, tick->step, tick->t, true));
    ++stale_commands_;
  }
  updater_.update();
}

void MracControllerNode::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  const double now = ros::Time::now().toSec();
  const auto decisions = [this](Event::Decision d) { return decisions_[static_cast<int>(d)]; };
  NodeStatus(stat)
      .problem(seq_.stale(), diagnostic_msgs::DiagnosticStatus::ERROR,
               "stale input: publishing safe commands, adaptation frozen")
      .problem(seq_.guard().rejected() > 0, diagnostic_msgs::DiagnosticStatus::WARN,
               "malformed states rejected")
      .problem(input_guard_.dropped() > 0, diagnostic_msgs::DiagnosticStatus::WARN,
               "input from foreign publishers dropped (~accept_from)")
      .problem(!reconf_->lastRefusal().empty(), diagnostic_msgs::DiagnosticStatus::WARN,
               "reconfigure refused: " + reconf_->lastRefusal())
      .summarize("adapting")
      .rows({{"mode", ctl_.mode()},
             {"stale", seq_.stale()},
             {"stale time [s]", seq_.guard().haveValid() ? seq_.guard().age(now) : -1.0},
             {"stale timeout [s]", params_.stale_timeout},
             {"stale episodes", seq_.staleEpisodes()},
             {"stale commands", stale_commands_},
             {"state rate [Hz]", state_rate_.update(states_received_, now)},
             {"states received", states_received_},
             {"states accepted", seq_.guard().accepted()},
             {"states rejected", seq_.guard().rejected()},
             {"last rejection", seq_.guard().lastRejection()},
             {"truths rejected", truth_guard_.rejected()},
             {"gaps", seq_.gaps()},
             {"controller steps", seq_.steps()},
             {"saturated steps", saturated_},
             {"onsets", onsets_},
             {"recoveries", recoveries_},
             {"resets", resets_},
             {"non-finite resets", reconf_->nonFiniteResets()},
             // pa_robust: DECISION events, and what the verifications (at onsets and DECISION
             // events) chose.
             {"decision events", decision_events_},
             {"decisions keep", decisions(Event::Decision::kKeep)},
             {"decisions fit", decisions(Event::Decision::kFit)},
             {"decisions memory", decisions(Event::Decision::kMemory)},
             {"decisions network", decisions(Event::Decision::kNetwork)},
             {"last decision", last_decision_.empty() ? std::string("none") : last_decision_},
             {"episodes", ctl_.network().state().episodes},
             {"plant restarts", seq_.restarts()},
             {"reconfigure changes applied", reconf_->applied()},
             {"reconfigure requests refused", reconf_->refused()},
             {"last reconfigure refusal", reconf_->lastRefusal()}})
      .guard(input_guard_);
}

std::unique_ptr<MracControllerNode> makeMracControllerNode(const NodeContext& ctx) {
  ControllerNodeParams params;
  if (!readNodeParams(ctx, readControllerNodeParams, &params)) return nullptr;
  for (const std::string& d : params.run.derived) ROS_INFO("derived at start: %s", d.c_str());
  try {
    auto node = std::make_unique<MracControllerNode>(ctx, params);
    node->start();
    return node;
  } catch (const std::exception& e) {
    // Validated above; this catches a weights file changed in between or a solver refusal.
    ctx.logConfigProblems({e.what()});
    ctx.end(kExitConfigError);
    return nullptr;
  }
}

int runMracControllerNode() { return spinProcessNode(makeMracControllerNode, true); }

}  // namespace ros1
}  // namespace preadaptive_mrac
