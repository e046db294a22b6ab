#pragma once
/// \file envelope.hpp
/// \brief The flight envelope the plant simulator checks on every step: a state or
/// command that is not finite, and angle of attack, pitch rate and elevator command beyond
/// the bounds of plant.envelope. ScenarioPlant checks it, so the batch loop and the plant node
/// (and any plant engine behind ScenarioPlant) see the same first exit.

#include <cmath>
#include <cstdint>
#include <string>

#include "preadaptive_mrac/core/sim/plant_conditions.hpp"
#include "preadaptive_mrac/core/types.hpp"
#include "preadaptive_mrac/params/plant_params.hpp"

namespace preadaptive_mrac {

/// \brief Key plant.envelope (optional; absent = the B-747 defaults of params/plant.yaml,
/// checked): enabled, max_alpha [rad], max_pitch_rate [rad/s], max_elevator_command [rad].
struct FlightEnvelope : FlightEnvelopeParams {};

/// \brief The first exit from the envelope: when, which bound, and the plant there.
struct EnvelopeExit {
  bool exited = false;
  std::int64_t step = 0;  ///< the sample of the exit (the command's, or the state's)
  double t = 0.0;         ///< its time t = step dt [s]
  /// "alpha", "pitch_rate", "elevator_command" or "non_finite" (a state or command that is not
  /// finite, which ends the run).
  std::string bound;
  std::string key;             ///< the plant.envelope key of the bound ("" for non_finite)
  double value = 0.0;          ///< the quantity that left (|alpha|, |q|, |u|; the offending number)
  double limit = 0.0;          ///< its bound (0 for non_finite)
  Vec x;                       ///< the true state at t
  double u_command = 0.0;      ///< the command of the step that was taken at t [rad]
  PlantConditions conditions;  ///< the plant's conditions record at t
  ConditionRows rows{true, false};  ///< its rows (the engine's only on an engine)
  /// A state or command was not finite (at the exit or later): the run ended at non_finite_t.
  bool non_finite = false;
  double non_finite_t = 0.0;
  /// \brief One line: "t = 5.213 s (step 5213): |alpha| = 0.2701 rad > 0.2618 rad
  /// (plant.envelope.max_alpha)".
  std::string describe() const;
};

/// \brief Checks one sample against the envelope and keeps the first exit.
class EnvelopeMonitor {
 public:
  /// \brief `engine`: the plant is an engine (plant.engine not linear), whose rows the exit's
  /// conditions record has.
  explicit EnvelopeMonitor(const FlightEnvelope& env = FlightEnvelope(), int alpha_index = 1,
                           bool engine = false)
      : env_(env), alpha_(alpha_index), engine_(engine) {
    reset();
  }
  void reset() {
    exit_ = EnvelopeExit();
    alpha_limit_ = env_.enabled ? env_.max_alpha : HUGE_VAL;
    q_limit_ = env_.enabled ? env_.max_pitch_rate : HUGE_VAL;
  }
  /// \brief The command u [rad] given at sample `step` (time t), with the state x there.
  void checkCommand(std::int64_t step, double t, double u, const Vec& x, const PlantConditions& c) {
    if (!std::isfinite(u)) {
      markNonFinite(t);
      record(step, t, "non_finite", "", u, 0.0, x, u, c);
    } else if (env_.enabled && !(std::abs(u) <= env_.max_elevator_command)) {
      record(step, t, "elevator_command", "max_elevator_command", std::abs(u),
             env_.max_elevator_command, x, u, c);
    }
  }
  /// \brief The state x at sample `step` (time t), reached with command u. Inline: a state
  /// inside costs two comparisons and a finiteness test per step.
  void checkState(std::int64_t step, double t, const Vec& x, double u, const PlantConditions& c) {
    const double a = alpha_ < x.size() ? std::abs(x[alpha_]) : 0.0;
    const double q = x.size() > 2 ? std::abs(x[2]) : 0.0;
    if (a <= alpha_limit_ && q <= q_limit_ && x.allFinite()) return;
    checkStateBeyond(step, t, x, u, c);
  }
  const EnvelopeExit& exit() const { return exit_; }
  /// \brief A state or command was not finite: the run must end.
  bool nonFinite() const { return exit_.non_finite; }

 private:
  void checkStateBeyond(std::int64_t step, double t, const Vec& x, double u,
                        const PlantConditions& c);
  void record(std::int64_t step, double t, const char* bound, const char* key, double value,
              double limit, const Vec& x, double u, const PlantConditions& c);
  FlightEnvelope env_;
  int alpha_;
  bool engine_ = false;
  double alpha_limit_ = HUGE_VAL, q_limit_ = HUGE_VAL;  // the bounds while they matter
  void markNonFinite(double t) {
    if (!exit_.non_finite) exit_.non_finite_t = t;
    exit_.non_finite = true;
  }
  EnvelopeExit exit_;
};

}  // namespace preadaptive_mrac
