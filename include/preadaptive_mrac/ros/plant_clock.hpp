#pragma once
/// \file plant_clock.hpp
/// \brief How the plant node's steps follow one another: lockstep (each step waits for the
/// controller's answer) or realtime (a wall-clock tick, the latest command held). The node
/// (plant_sim_node.hpp) publishes, advances and reports; its clock runs the loop and decides
/// what a command means.

#include <ros/ros.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "preadaptive_mrac/ElevatorCommand.h"
#include "preadaptive_mrac/RecorderProgress.h"
#include "preadaptive_mrac/ros/latency_stats.hpp"
#include "preadaptive_mrac/ros/node_status.hpp"

namespace preadaptive_mrac {
namespace ros1 {

class PlantSimNode;

/// \brief Wall time [s] (ROS's wall clock).
inline double wallNow() { return ros::WallTime::now().toSec(); }

/// \brief One of the plant's clocks, a part of the node (it reads and drives the node's
/// simulator, publishers and counters). Methods marked "locked" run under the node's mutex.
class PlantClock {
 public:
  explicit PlantClock(PlantSimNode& node) : node_(node) {}
  virtual ~PlantClock() = default;
  PlantClock(const PlantClock&) = delete;
  PlantClock& operator=(const PlantClock&) = delete;

  /// \brief Locked: a finite command admitted by ~accept_from, received at wall time
  /// `arrival` [s]. False when it answers nothing (counted as the clock says); else its round
  /// trip [us] in *latency_us.
  virtual bool take(const ElevatorCommand& msg, double arrival, double* latency_us) = 0;
  /// \brief The recorder's progress on some state topic (lockstep waits for it).
  virtual void progress(const RecorderProgress& /*msg*/) {}
  /// \brief State `step` was published (at wall time `wall` [s]).
  virtual void published(std::uint64_t /*step*/, double /*wall*/) {}
  /// \brief Run the scenario; the node's exit code (PlantSimNode::run()).
  virtual int run() = 0;
  /// \brief Close this clock's own topics (~linger).
  virtual void close() {}
  /// \brief Locked: the clock's problem for the diagnostics summary (before the node's).
  virtual void problems(NodeStatus& /*status*/) const {}
  /// \brief Locked: the clock's diagnostics rows.
  virtual void rows(NodeStatus& status) const = 0;
  /// \brief Locked: the clock's fields of the run report.
  virtual void report(RunReport* r) const = 0;

 protected:
  PlantSimNode& node_;
};

/// \brief Lockstep: for k = 0 .. total-1 publish /clock = t_k, truth k, state k, then wait
/// (bounded by ~command_timeout) for the command whose step is k, re-sending the state every
/// ~resend_interval, and advance with its u; a recorder that falls ~max_recorder_lag steps
/// behind holds the loop.
class LockstepClock : public PlantClock {
 public:
  explicit LockstepClock(PlantSimNode& node);
  bool take(const ElevatorCommand& msg, double arrival, double* latency_us) override;
  void progress(const RecorderProgress& msg) override;
  void published(std::uint64_t step, double wall) override;
  int run() override;
  void close() override { clock_pub_.shutdown(); }
  void rows(NodeStatus& status) const override;
  void report(RunReport* r) const override;

 private:
  /// \brief Serve the node's queue, in waits of at most `slice` s, until done() or
  /// ~command_timeout from now; `between` (if any) runs before each wait with the wall time.
  /// True when done; false on timeout or shutdown (the caller tells them apart by ctx.ok()).
  bool serveUntil(const std::function<bool()>& done, double slice,
                  const std::function<void(double)>& between);
  /// \brief Back-pressure: wait (bounded by ~command_timeout) until the recorder has written
  /// state `step` - `lag`. False on timeout or shutdown.
  bool waitForRecorder(std::uint64_t step, std::uint64_t lag);
  /// \brief At the run's end: wait (bounded by ~command_timeout, a warning then) until a
  /// recorder that records the commands has written the last one this node took, so that the
  /// launch it ends next does not cut that command off the bag.
  void waitForRecordedCommands();
  /// \brief Before step 1: wait (bounded by ~command_timeout, a warning then) until a recorder
  /// that records the commands has written the command of step 0. A subscriber counts a
  /// publisher before the publisher has taken the connection, so only a written command shows
  /// that the recorder gets every later one (one TCP connection keeps their order). Until then
  /// state 0 is published again every 20 ms: the controller answers a repeated state with the
  /// same command, and the recorder writes neither twice.
  void waitForRecordedFirstCommand();
  /// \brief Wait for the answer to step k (re-sending its state); false on timeout (logged)
  /// or shutdown, *give_up set on timeout.
  bool awaitAnswer(std::uint64_t k, double* u, bool* give_up);

  ros::Publisher clock_pub_;  ///< ~publish_clock: clock (latched)
  bool have_progress_ = false;
  std::uint64_t recorded_step_ = 0;      ///< last state step the recorder has written
  bool have_cmd_progress_ = false;       ///< the recorder reports the command topic too
  std::uint64_t recorded_cmd_step_ = 0;  ///< last command step the recorder has written
  std::int64_t stale_cmds_ignored_ = 0;  ///< the controller's staleness-timer commands
  std::int64_t resent_ = 0, recorder_waits_ = 0;
  std::uint64_t published_step_ = 0;  ///< the last state published (the one awaited)
  double published_wall_ = 0.0;       ///< its wall time of publication [s]
};

/// \brief Realtime: a wall-clock tick every 1/~rate s (absolute deadlines) advances with the
/// latest valid command while it is fresh (~cmd_timeout), else with trim (u = 0).
class RealtimeClock : public PlantClock {
 public:
  explicit RealtimeClock(PlantSimNode& node);
  bool take(const ElevatorCommand& msg, double arrival, double* latency_us) override;
  int run() override;
  void problems(NodeStatus& status) const override;
  void rows(NodeStatus& status) const override;
  void report(RunReport* r) const override;

 private:
  /// \brief Locked: the elevator of the step due now (the held command, or trim), counting
  /// stale and trim steps. False when no command came within ~start_timeout (logged).
  bool heldCommand(double first_cmd_deadline, double* u);

  std::int64_t trim_steps_ = 0;     ///< steps held at trim (no fresh command)
  std::int64_t trim_episodes_ = 0;  ///< times the plant fell back to trim
  bool in_trim_ = false;
  std::int64_t stale_steps_ = 0, late_ticks_ = 0;
  LatencyStats tick_late_us_;  ///< wake-up after each tick's deadline [us]
};

/// \brief The clock ~clock names.
std::unique_ptr<PlantClock> makePlantClock(PlantSimNode& node);

}  // namespace ros1
}  // namespace preadaptive_mrac
