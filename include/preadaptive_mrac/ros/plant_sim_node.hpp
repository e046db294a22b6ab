#pragma once
/// \file plant_sim_node.hpp
/// \brief ROS wiring of the plant simulator: the core ScenarioPlant (the same stepping object
/// the batch loop uses), published as plant/state, plant/truth, tf and (lockstep) /clock.

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "preadaptive_mrac/ElevatorCommand.h"
#include "preadaptive_mrac/PlantState.h"
#include "preadaptive_mrac/PlantTruth.h"
#include "preadaptive_mrac/RecorderConnections.h"
#include "preadaptive_mrac/RecorderProgress.h"
#include "preadaptive_mrac/core/closed_loop.hpp"
#include "preadaptive_mrac/ros/latency_stats.hpp"
#include "preadaptive_mrac/ros/node_context.hpp"
#include "preadaptive_mrac/ros/node_params.hpp"
#include "preadaptive_mrac/ros/plant_clock.hpp"
#include "preadaptive_mrac/ros/publisher_guard.hpp"
#include "preadaptive_mrac/ros/rate_meter.hpp"

namespace preadaptive_mrac {
namespace ros1 {

/// \brief The plant simulator node.
///
/// Topics are relative to the node's namespace, so a launch file can put a plant and a
/// controller pair under /rac and another under /pa:
/// - publishes plant/state (PlantState), plant/truth (PlantTruth), /tf, and in lockstep /clock;
/// - subscribes controller/elevator_cmd (ElevatorCommand, tcpNoDelay), taking commands only
///   from the publishers of ~accept_from (when set).
///
/// The steps follow the node's clock (plant_clock.hpp): LockstepClock waits for each step's
/// answer, RealtimeClock ticks on the wall clock and holds the latest command.
class PlantSimNode {
 public:
  /// \brief Advertises and subscribes; params must have been validated.
  PlantSimNode(const NodeContext& ctx, const PlantNodeParams& params);

  /// \brief Run the scenario to its end (or until shutdown). Returns the process exit code:
  /// 0 on completion or interruption, kExitRuntimeError when the engine fails mid-run (a
  /// JSBSim process that died: logged, the run stopped), on a start or command timeout (no
  /// controller subscribed within ~start_timeout; lockstep: no command within
  /// ~command_timeout; realtime: no valid command within ~start_timeout of the first state).
  /// With ~linger, a completed run closes its topics and returns only at shutdown. Blocks: a
  /// nodelet runs it in a thread of its own; it returns soon after ctx.stop().
  int run();

  /// \brief The report of the run so far (latency, missed steps, wall time).
  RunReport report() const;

 private:
  friend class LockstepClock;
  friend class RealtimeClock;
  friend std::unique_ptr<PlantClock> makePlantClock(PlantSimNode& node);

  void commandCallback(const ros::MessageEvent<ElevatorCommand const>& event);
  /// \brief Wait (bounded by ~start_timeout) for the subscribers of ~min_state_subscribers and
  /// ~min_truth_subscribers. False on timeout (logged, naming what is missing) or shutdown.
  bool waitForSubscribers();
  /// \brief What the start-up wait lacks: subscriber counts, and whether a controller exists.
  std::string missingPeers() const;
  /// \brief True when no recorder is expected, or the recorder is connected to as many
  /// publishers of the command topic as this node is (so it gets the command of step 0).
  bool recorderHasTheCommands() const;
  /// \brief Why no command came (for the give-up errors): no publisher, a silent controller
  /// (`silent`: "did not answer"), and any commands dropped by ~accept_from.
  std::string noCommandCause(const char* silent) const;
  /// \brief With ~linger after a completed run: close every topic, then idle until shutdown.
  void linger();
  /// \brief ~cpu_affinity (and `rt_priority`) for the loop thread; logs refusals.
  void schedule(int rt_priority, bool receiving_thread);
  /// \brief Publish truth then state of the current step, and tf every ~tf_decimation steps.
  void publishSample(const ros::Time& stamp);
  /// \brief Advance the plant by one step with elevator u [rad]; integrates the pitch angle.
  void advance(double u);
  void finish(bool completed);
  /// \brief diagnostic_updater task: rates, rejected commands, command age, trim, saturation.
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);
  static ros::Time simStamp(double t);

  NodeContext ctx_;
  ros::NodeHandle nh_;
  ros::CallbackQueue queue_;  ///< the command and progress subscriptions, served by run()
  ros::NodeHandle own_;       ///< nh_ on queue_
  PlantNodeParams params_;
  ScenarioPlant sim_;
  ros::Publisher state_pub_, truth_pub_;
  /// tf (tf2_msgs/TFMessage) and clock, relative: /tf and /clock at the top level, under the
  /// namespace otherwise, so that runs side by side do not mix (a tf2_ros::TransformBroadcaster
  /// would publish on /tf whatever the namespace, and a nodelet's remappings do not reach it).
  ros::Publisher tf_pub_;
  /// plant/done: the last state, latched, once the run completed; kept open while lingering
  /// so that a run monitor that subscribed late still learns that the run completed.
  ros::Publisher done_pub_;
  PlantState::ConstPtr last_state_;
  ros::Subscriber cmd_sub_, progress_sub_;
  ros::Subscriber ready_sub_;  ///< controller/ready (~wait_for_controller, lockstep)
  /// The recorder's ~connections (beside its ~progress), read on queue_ before step 0: the
  /// publishers of the command topic it is connected to (-1: none said yet; the recorder's
  /// topics without the command topic: no wait).
  ros::Subscriber connections_sub_;
  int recorder_cmd_publishers_ = -1;
  bool recorder_records_commands_ = true;
  bool controller_ready_ = false;  ///< set on queue_ (the plant's own thread)
  diagnostic_updater::Updater updater_;
  PublisherGuard cmd_guard_;  ///< ~accept_from on the command topic
  std::string cmd_topic_;     ///< resolved command topic, for the guard's warnings

  double applied_u_ = 0.0;  ///< elevator over the previous step [rad]

  mutable std::mutex mutex_;  ///< guards the fields below and the clock's counters
  bool have_cmd_ = false;
  std::uint64_t cmd_step_ = 0;
  double cmd_u_ = 0.0;
  std::int64_t commands_received_ = 0, commands_ignored_ = 0;
  std::int64_t commands_rejected_ = 0;  ///< non-finite u: counted, never applied
  std::int64_t saturated_steps_ = 0;    ///< steps where the actuator limited the command
  bool envelope_logged_ = false;        ///< the ERROR of the envelope exit was logged
  bool cmd_stale_ = false;              ///< the held command came from the staleness timer
  double last_cmd_wall_ = 0.0;          ///< wall time [s] of the last accepted command
  std::string last_rejection_;
  RateMeter step_rate_, cmd_rate_;  ///< wall-clock rates for the diagnostics
  LatencyStats latency_us_;         ///< round trips [us], in memory that does not grow with the run
  std::string scheduling_;          ///< the loop thread's scheduling
  double wall_start_ = 0.0, wall_end_ = 0.0;
  bool completed_ = false;
  std::unique_ptr<PlantClock> clock_;  ///< ~clock: the loop; made last
};

/// \brief The node, or nullptr when its plant cannot start (plant.engine jsbsim: JSBSim not
/// installed, an aircraft that does not load, a failed trim): ROS_FATAL saying what and how
/// to fix it, ctx.end(kExitConfigError). Process and nodelet.
std::unique_ptr<PlantSimNode> makePlantSimNode(const NodeContext& ctx,
                                               const PlantNodeParams& params);

/// \brief Everything main() does after ros::init(): read ~ (every problem at once; ROS_FATAL
/// each and return kExitConfigError without advertising), build the node, run it.
int runPlantSimNode();

}  // namespace ros1
}  // namespace preadaptive_mrac
