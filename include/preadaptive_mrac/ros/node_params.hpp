#pragma once
/// \file node_params.hpp
/// \brief Parameters of the two ROS nodes, read from a ParamValue tree (the node's private
/// namespace) with every problem collected at once. ROS-free, so it is tested without a master.

#include <cstdint>
#include <string>
#include <vector>

#include "preadaptive_mrac/core/input_guard.hpp"
#include "preadaptive_mrac/core/params.hpp"
#include "preadaptive_mrac/io/setup.hpp"

namespace preadaptive_mrac {
namespace ros1 {

/// \brief How the plant node advances time (and, for the controller, which clock measures
/// staleness).
enum class ClockMode {
  kLockstep,  ///< one step per answered command, simulation time in the stamps: deterministic, fast
  kRealtime,  ///< wall-clock timer, zero-order hold on the latest command
};
const char* clockModeName(ClockMode m);

/// \brief Everything plant_sim_node reads from `~`.
struct PlantNodeParams {
  RunConfig run;                            ///< plant and scenario sections (controller unused)
  double dt = 0.001;                        ///< ~dt: integration step = sample time [s], (0, 1]
  ClockMode clock = ClockMode::kLockstep;   ///< ~clock: lockstep | realtime
  double rate = 1000.0;                     ///< ~rate: realtime tick rate [Hz], (0, 100000]
  bool publish_clock = true;                ///< ~publish_clock: lockstep publishes /clock
  int clock_decimation = 1;                 ///< ~clock_decimation: /clock every N steps (>= 1)
  std::string world_frame = "world";        ///< ~world_frame: tf parent frame
  std::string body_frame = "body";          ///< ~body_frame: pitched by the pitch angle
  std::string velocity_frame = "velocity";  ///< ~velocity_frame: body rotated by alpha
  int tf_decimation = 10;                   ///< ~tf_decimation: tf every N steps (>= 1)
  int min_state_subscribers = 1;            ///< ~min_state_subscribers: wait for them before step 0
  int min_truth_subscribers = 0;            ///< ~min_truth_subscribers: wait for them before step 0
  /// ~start_timeout: wall time [s] to wait for those subscribers (the controller) and, in
  /// realtime, for the first valid command after the first state; then exit 3. 0 = forever.
  double start_timeout = 15.0;
  double command_timeout = 10.0;  ///< ~command_timeout: lockstep wait for one command [s] (> 0)
  double resend_interval = 1.0;   ///< ~resend_interval: lockstep re-publishes an unanswered
                                  ///< state after this wall time [s]; 0 = never
  /// ~wait_for_controller: lockstep: before step 0 also wait for the controller's latched
  /// controller/ready (sent once it takes states). In a nodelet manager a recorder's state
  /// subscription is the controller's connection too, so the subscriber count cannot tell
  /// whether the controller has subscribed; without this its first state could be lost and
  /// re-sent after ~resend_interval (a duplicate step 0 in the bag).
  bool wait_for_controller = false;
  double shutdown_grace = 0.5;          ///< ~shutdown_grace: wall time kept alive after the end [s]
  std::string latency_report;           ///< ~latency_report: JSON summary path ("" = none)
  int queue_size = 0;                   ///< ~queue_size: per-subscriber outgoing queue of the
                                        ///< per-step topics; 0 = unbounded (nothing dropped)
  std::string recorder_progress_topic;  ///< ~recorder_progress_topic: bag_recorder_node's
                                        ///< ~progress; lockstep waits for it ("" = no recorder)
  int max_recorder_lag = 2000;  ///< ~max_recorder_lag: steps the recorder may fall behind (>= 1)
  /// ~cmd_timeout: realtime only: with no valid command received within this wall time [s]
  /// the plant holds trim (u = 0) until one arrives; (0, 1e6]. Lockstep waits instead.
  double cmd_timeout = 0.05;
  double diagnostic_period = 1.0;  ///< ~diagnostic_period: read by diagnostic_updater [s]
  /// ~linger: after a completed run, unadvertise every topic and stay alive (idle) until shut
  /// down, instead of exiting 0. Lets a launch file mark the plant required (a failing plant
  /// ends the launch) where its normal end must not (compare.launch: two plants).
  bool linger = false;
  /// Every optional key left out and filled with its default ("<key> = <value>", resolved
  /// names): the node's own (~dt, ~clock, ...) and those of the plant and scenario sections.
  std::vector<std::string> defaults_used;
  /// ~rt_priority: realtime only: run the tick thread under SCHED_FIFO at this priority
  /// [1, 99]; 0 = normal scheduling. Without the right (CAP_SYS_NICE, rtprio limit) the plant
  /// warns once and keeps normal scheduling.
  int rt_priority = 0;
  /// ~cpu_affinity: realtime only: pin the tick thread to this CPU [0, 1023]; -1 = any CPU.
  int cpu_affinity = -1;
  /// ~accept_from: node names (caller ids) whose commands are taken on controller/elevator_cmd,
  /// relative ones resolved in the node's namespace; others are dropped and counted
  /// (PublisherGuard). Empty = any publisher.
  std::vector<std::string> accept_from;
};

/// \brief Everything mrac_controller_node reads from `~`.
struct ControllerNodeParams {
  RunConfig run;                    ///< plant (A, B, B1r) and controller sections
  std::string weights_in;           ///< ~weights_in: network weights loaded at start ("" = seed)
  std::string weights_out;          ///< ~weights_out: saved after each episode and at shutdown
  bool save_every_episode = true;   ///< ~save_every_episode: save after each learning episode
  int min_command_subscribers = 1;  ///< ~min_command_subscribers: wait before taking states
  int min_status_subscribers = 0;   ///< ~min_status_subscribers: same for status and attention
  double start_timeout = 15.0;      ///< ~start_timeout: wall time to wait for them [s]; 0 = forever
  int truth_buffer = 10000;         ///< ~truth_buffer: max states waiting for their truth (>= 1)
  /// ~stale_policy: baseline_hold | zero, the command answering a rejected state (NaN, Inf,
  /// wrong size): the LQR baseline of the last valid state, or 0.
  StalePolicy stale_policy = StalePolicy::kBaselineHold;
  int queue_size = 0;  ///< ~queue_size: per-subscriber outgoing queue of the
                       ///< per-step topics; 0 = unbounded (nothing dropped)
  /// ~stale_timeout: with no valid state for this time [s] (in ~clock's time) the controller
  /// publishes the ~stale_policy command at its sample rate and does not adapt; (0, 1e6].
  double stale_timeout = 0.05;
  /// ~clock: lockstep | realtime (default). lockstep: staleness is measured in the states'
  /// own stamps (simulation time), so a plant that waits (for a recorder, a restarted peer)
  /// never makes the controller stale, and no ROS clock (/clock, /use_sim_time, shared by
  /// every run on the master) is needed; realtime: in ROS time at receipt.
  ClockMode clock = ClockMode::kRealtime;
  double diagnostic_period = 1.0;  ///< ~diagnostic_period: read by diagnostic_updater [s]
  /// Every optional key left out and filled with its default (the node's own, then the plant
  /// and controller sections').
  std::vector<std::string> defaults_used;
  /// ~rt_priority: SCHED_FIFO priority [1, 99] of each thread that runs the state callback
  /// (the spinning thread; in a nodelet manager its worker threads); 0 = normal scheduling.
  /// Refused (no CAP_SYS_NICE): a warning, normal scheduling.
  int rt_priority = 0;
  int cpu_affinity = -1;  ///< ~cpu_affinity: pin those threads to this CPU; -1 = any
  /// ~accept_from: node names (caller ids) whose states and truths are taken, as the plant's.
  std::vector<std::string> accept_from;
};

/// \brief One start-up line naming every optional key filled with its default:
/// "optional keys filled with defaults: k1 = v1, k2 = v2" (or "...: none").
std::string defaultsLine(const std::vector<std::string>& defaults_used);

/// \brief Read and validate plant_sim_node's private parameters. Throws ConfigError listing
/// every problem, each naming its key in `style` (e.g. "/plant_sim/dt").
PlantNodeParams readPlantNodeParams(const ParamValue& tree, const KeyStyle& style);

/// \brief Read and validate mrac_controller_node's private parameters, including the design
/// check of readRunConfig (A, B not stabilisable etc.) and a readable ~weights_in of the
/// right size. Throws ConfigError listing every problem.
ControllerNodeParams readControllerNodeParams(const ParamValue& tree, const KeyStyle& style);

}  // namespace ros1
}  // namespace preadaptive_mrac
