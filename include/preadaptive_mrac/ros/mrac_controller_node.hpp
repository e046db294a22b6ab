#pragma once
/// \file mrac_controller_node.hpp
/// \brief ROS wiring of the core Controller: one controller step per plant/state message.

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>

#include <array>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <string>

#include "preadaptive_mrac/AdaptationStatus.h"
#include "preadaptive_mrac/AttentionEvent.h"
#include "preadaptive_mrac/ElevatorCommand.h"
#include "preadaptive_mrac/PlantState.h"
#include "preadaptive_mrac/PlantTruth.h"
#include "preadaptive_mrac/core/control/input_guard.hpp"
#include "preadaptive_mrac/core/controller/controller.hpp"
#include "preadaptive_mrac/core/step_sequencer.hpp"
#include "preadaptive_mrac/ros/attention_msg.hpp"
#include "preadaptive_mrac/ros/node_context.hpp"
#include "preadaptive_mrac/ros/node_params.hpp"
#include "preadaptive_mrac/ros/publisher_guard.hpp"
#include "preadaptive_mrac/ros/rate_meter.hpp"

namespace preadaptive_mrac {
namespace ros1 {

class ControllerReconfigure;

/// \brief The preadaptive MRAC controller node.
///
/// Subscribes plant/state (tcpNoDelay) and, in the modes that need the simulation truth
/// (Controller::needsTruth(): pa_learn_exact, oracle), plant/truth; publishes
/// controller/elevator_cmd (answering each state's step), controller/attention (attention
/// events and pa_robust's decisions) and controller/status (every step). All topics are
/// relative to the node's namespace. States and truths are taken only from the publishers of
/// ~accept_from (when set).
class MracControllerNode {
 public:
  /// \brief Builds the controller (K, P at start-up), loads ~weights_in, advertises.
  MracControllerNode(const NodeContext& ctx, const ControllerNodeParams& params);
  ~MracControllerNode();

  /// \brief Does not block: once the wanted subscribers are connected (polled by a timer),
  /// subscribe and start the staleness timer; after ~start_timeout without them, end the node
  /// with kExitRuntimeError. Callbacks run wherever ctx.nh()'s queue is served.
  void start();
  /// \brief Stop taking states, save ~weights_out (unless the node failed), print a summary.
  /// Idempotent; called after the spin (process) or on unload (nodelet).
  void finish();

 private:
  void stateCallback(const ros::MessageEvent<PlantState const>& event);
  void truthCallback(const ros::MessageEvent<PlantTruth const>& event);
  /// \brief States waiting for their truth, in order, as far as the truth has arrived.
  void drainPending();
  /// \brief A state through the step sequencer (theta: its truth, or nullptr), then its
  /// answer published and the sequence's news logged.
  void process(const PlantState& msg, const Vec* theta);
  /// \brief What the sequencer noticed about the order of the states (restart, gap, the
  /// plant's last step, valid again after stale input), logged.
  void logSequence(const PlantState& msg, const SampleOutcome& o);
  /// \brief A controller step's answer: the command, its event, the status; the weights
  /// saved after a learning episode (~save_every_episode).
  void publishStep(const PlantState& msg, StepOutput* out);
  /// \brief An attention event: counted, published and logged.
  void publishEvent(const PlantState& msg, const Event& e);
  /// \brief Answer a rejected state with the safe command (~stale_policy) of the last valid one.
  void answerRejected(const PlantState& msg, const std::string& why);
  /// \brief Every sample time: with no valid state for ~stale_timeout, publish the safe
  /// command (~stale_policy) of the last valid state, flagged `stale`; then diagnostics.
  void staleTimerCallback(const ros::TimerEvent&);
  /// \brief ~clock realtime: no state at all (valid or not) for ~plant_lost_samples sample
  /// times of this node's own running (plant_silence_: a pause of this process counts at
  /// most a quarter of that): log it once, stop the staleness timer and end the node
  /// (kExitRuntimeError).
  bool plantLost();
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);
  bool subscribersReady() const;
  void subscribe();
  /// \brief The safe command (~stale_policy on the last valid state): the answer to a rejected
  /// state (stale = false) and the staleness timer's command (stale = true).
  ElevatorCommand::ConstPtr safeCommand(const ros::Time& stamp, std::uint64_t step, double t,
                                        bool stale);
  /// \brief at_end: after the spin, when rosconsole may no longer print.
  void saveWeights(const char* why, bool at_end = false);
  void fatal(const std::string& what);

  NodeContext ctx_;
  ros::NodeHandle nh_;
  ControllerNodeParams params_;
  Controller ctl_;
  StepSequencer seq_;  ///< the states' order, validity and staleness, and the controller step
  ros::Publisher cmd_pub_, attention_pub_, status_pub_;
  ros::Publisher ready_pub_;  ///< controller/ready, latched true once states are taken
  ros::Subscriber state_sub_, truth_sub_;
  ros::Timer stale_timer_;
  ros::WallTimer start_timer_;
  double start_wall_ = 0.0;  ///< wall time [s] start() began waiting for subscribers
  diagnostic_updater::Updater updater_;
  PublisherGuard input_guard_;             ///< ~accept_from on plant/state and plant/truth
  std::string state_topic_, truth_topic_;  ///< resolved, for the guard's warnings

  ElevatorCommand::ConstPtr last_cmd_;  ///< the answer to the last state (sent again on a repeat)
  InputGuard truth_guard_;

  bool failed_ = false, finished_ = false;
  std::int64_t episodes_saved_ = -1;

  // Staleness: ~clock lockstep measures it in the states' stamps (simulation time, so a
  // lockstep plant that pauses does not make the controller stale, and no ROS clock shared
  // with other runs is involved); realtime in ROS time.
  double latest_stamp_ = 0.0;  ///< lockstep: stamp [s] of the latest state received
  /// ROS time since the latest admitted state (valid or not), pauses of this process capped
  SilenceClock plant_silence_;
  /// \brief Now for the staleness check [s]: the latest state's stamp in lockstep, else ROS time.
  double staleNow() const;
  std::int64_t stale_commands_ = 0, rejected_answers_ = 0;
  std::int64_t states_received_ = 0, saturated_ = 0, onsets_ = 0, resets_ = 0, recoveries_ = 0;
  RateMeter state_rate_;  ///< states per second of ROS time, for the diagnostics

  // pa_robust's verifications, for the diagnostics.
  std::int64_t decision_events_ = 0;         ///< DECISION events
  std::array<std::int64_t, 5> decisions_{};  ///< decisions (onsets and DECISION) by kind
  std::string last_decision_;                ///< e.g. "fit at t = 45.052 s (score ...)"
  /// the choice ("fit", "memory #2", ...) last logged at INFO in this phase ("" after a
  /// recovery, onset or other event without a verification): a repeat is logged at DEBUG
  std::string logged_choice_;

  /// dynamic_reconfigure (~reconfigure) and controller/param_change.
  std::unique_ptr<ControllerReconfigure> reconf_;

  std::map<std::uint64_t, Vec> truth_;        ///< pa_learn_exact, oracle: theta by step
  std::deque<PlantState::ConstPtr> pending_;  ///< states waiting for their truth
  bool have_truth_ = false;
  std::uint64_t last_truth_step_ = 0;
};

/// \brief Read ~ (every problem at once: ROS_FATAL each, ctx.end(kExitConfigError), nothing
/// advertised, nullptr), build the node and start() it. Shared by the node and the nodelet.
std::unique_ptr<MracControllerNode> makeMracControllerNode(const NodeContext& ctx);

/// \brief Everything main() does after ros::init(): makeMracControllerNode, spin until
/// shutdown, finish(); returns the exit code (0, kExitConfigError, kExitRuntimeError).
int runMracControllerNode();

}  // namespace ros1
}  // namespace preadaptive_mrac
