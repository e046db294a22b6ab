#pragma once
/// \file step_sequencer.hpp
/// \brief The controller's side of a loop whose plant runs elsewhere (the ROS controller node):
/// the order of the plant's states (a repeat, a gap, a restarted plant), their validity and
/// staleness, and the controller step. Numbers in, decisions out: no transport, no clock.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "preadaptive_mrac/core/control/input_guard.hpp"
#include "preadaptive_mrac/core/controller/controller.hpp"

namespace preadaptive_mrac {

/// \brief One state of the plant as the transport delivered it.
struct PlantSample {
  std::uint64_t step = 0;
  double t = 0.0;             ///< sample time [s]
  double dt = 0.0;            ///< the plant's step [s]
  const double* x = nullptr;  ///< measured state, `size` entries
  std::size_t size = 0;       ///< entries of x as sent (checked against the plant's n)
  double r = 0.0;             ///< command [rad]
  /// Elevator the plant applied over the last step [rad]; not finite: not reported.
  double elevator = std::numeric_limits<double>::quiet_NaN();
  std::uint64_t total_steps = 0;  ///< the plant's run length in steps (0: not known)
};

/// \brief What became of a state, and what there is to say about the sequence.
struct SampleOutcome {
  enum class Kind {
    kStepped,        ///< the controller stepped: `out` is its answer
    kRepeated,       ///< the step just answered, again (its command was lost): answer it again
    kRejected,       ///< malformed (`why`): answer with safeCommand(), the controller untouched
    kBadSampleTime,  ///< the plant's step differs from the controller's sample time: fatal
    kStepFailed,     ///< the controller step threw (`why`): fatal
  };
  Kind kind = Kind::kStepped;
  std::string why;
  StepOutput out;  ///< kStepped: the controller's answer
  /// The plant restarted (its step went back): the step before; the controller was reset.
  std::optional<std::uint64_t> restarted_after;
  /// States first .. last never arrived (the step jumped ahead).
  std::optional<std::pair<std::uint64_t, std::uint64_t>> missing;
  bool finished = false;            ///< the plant's last step, answered for the first time
  std::optional<double> stale_for;  ///< valid again after this long stale [s]
};

/// \brief A tick of the staleness timer while the input is stale: the step the safe command
/// (safeCommand()) stands in for.
struct StaleTick {
  bool began = false;      ///< the input has just gone stale (the first tick of an episode)
  std::uint64_t step = 0;  ///< the step the command stands for
  double t = 0.0;          ///< its sample time [s]
};

/// \brief How long the plant has been silent, as this process saw it: the time since the last
/// state, where an interval between two asks longer than `max_gap` (this process itself did
/// not run: stopped, or starved of CPU) counts as `max_gap`. A process paused for seconds
/// together with its plant (both nodelets of one manager, or the whole machine) must not take
/// its own pause for the plant's silence when both resume; a plant that is gone is still found
/// after the timeout, later only by the capped pauses.
class SilenceClock {
 public:
  /// \brief `max_gap` [s]: the most one interval between two asks counts.
  explicit SilenceClock(double max_gap) : max_gap_(max_gap) {}
  /// \brief A state arrived at `now` [s].
  void heard(double now) {
    silent_ = 0.0;
    last_ = now;
    heard_ = true;
  }
  /// \brief The silence [s] as of `now`: 0 before the first state. Ask it at every tick.
  double silentFor(double now) {
    if (!heard_) return 0.0;
    const double gap = now > last_ ? now - last_ : 0.0;
    silent_ += gap < max_gap_ ? gap : max_gap_;
    last_ = now;
    return silent_;
  }

 private:
  double max_gap_;
  double silent_ = 0.0, last_ = 0.0;
  bool heard_ = false;
};

/// \brief Sequences a remote plant's states into controller steps.
///
/// States of one publisher arrive in order: a step going back is a new plant run (the
/// controller is reset), the same step again a lost command (answered again, no second
/// step), a step ahead a gap (counted). A malformed state is rejected (the plant gets the safe
/// command, ~stale_policy on the last valid state; the controller sees nothing). With no valid
/// state for the stale timeout, onTimer() gives the next step for the safe command at every
/// tick, until a valid state comes back or after the plant's last step.
class StepSequencer {
 public:
  /// \brief `ctl` is stepped by onSample(); `n` the state's size; `sample_time` [s] the
  /// controller's (the plant's step must equal it); `stale_timeout` [s].
  StepSequencer(Controller* ctl, int n, double sample_time, double stale_timeout,
                StalePolicy policy);

  /// \brief One state. `theta`: its truth (the modes that need it), or null. `refresh` [s]:
  /// the time a valid state refreshes the staleness with; `now` [s]: the staleness clock.
  SampleOutcome onSample(const PlantSample& s, const Vec* theta, double refresh, double now);
  /// \brief At every sample time of the staleness clock `now` [s]: the step to send the safe
  /// command for while the input is stale (none while fresh, before the first valid state,
  /// after the plant's last step).
  std::optional<StaleTick> onTimer(double now);
  /// \brief The safe command: the stale policy on the last valid state [rad] (through the
  /// controller's actuator limits, so it moves the controller's last command).
  double safeCommand() { return ctl_->safeCommand(x_last_valid_, policy_); }

  const Vec& x() const { return x_; }  ///< the state of the last step
  const InputGuard& guard() const { return guard_; }
  bool stale() const { return stale_; }
  std::uint64_t lastValidStep() const { return last_valid_step_; }
  std::uint64_t lastStep() const { return last_step_; }  ///< step of the last state
  bool runOver() const { return run_over_; }     ///< the plant's last step has been answered
  std::int64_t steps() const { return steps_; }  ///< controller steps
  std::int64_t gaps() const { return gaps_; }
  std::int64_t restarts() const { return restarts_; }
  std::int64_t staleEpisodes() const { return stale_episodes_; }

 private:
  // The order of s: false for a repeat (nothing more to do); notes a restart or a gap.
  bool sequence(const PlantSample& s, SampleOutcome* o);

  Controller* ctl_;
  int n_;
  double sample_time_;
  StalePolicy policy_;
  InputGuard guard_;
  Vec x_, x_last_valid_;
  bool dt_checked_ = false, have_last_ = false;
  std::uint64_t last_step_ = 0;
  std::uint64_t last_valid_step_ = 0;  ///< step of the last valid state
  double last_valid_t_ = 0.0;          ///< its sample time [s]
  std::uint64_t safe_step_ = 0;        ///< step of the last command from the staleness timer
  bool stale_ = false;
  double stale_since_ = 0.0;  ///< staleness clock [s] when the input went stale
  /// The last valid state was the plant's last step: no stale commands after it (a later
  /// state, a restarted plant, clears it).
  bool run_over_ = false;
  std::int64_t steps_ = 0, gaps_ = 0, restarts_ = 0, stale_episodes_ = 0;
};

}  // namespace preadaptive_mrac
