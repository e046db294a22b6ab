#pragma once
/// \file actuator.hpp
/// \brief The parts of the elevator actuator the plant simulator applies to a command, each
/// testable alone: transport delay, first-order servo lag, and the chain that runs them in
/// order (delay, lag, then the position and rate limits of ActuatorLimits).

#include <cstdint>
#include <vector>

#include "preadaptive_mrac/core/sim/plant.hpp"

namespace preadaptive_mrac {

/// \brief A pure delay of whole samples: the command pushed at sample k comes out at k + d.
/// Before any command has come through, the output is the actuator's initial state (0 rad).
class TransportDelay {
 public:
  /// \brief d = `steps` >= 0 samples (0: pass-through).
  explicit TransportDelay(std::int64_t steps = 0);
  /// \brief Delay of `delay` [s] at sample time `dt` [s], rounded to whole samples.
  static std::int64_t stepsFor(double delay, double dt);
  /// \brief Push the command of this sample [rad]; returns the one of d samples ago (0 before).
  double push(double u);
  void reset();
  std::int64_t steps() const { return static_cast<std::int64_t>(buf_.size()); }

 private:
  std::vector<double> buf_;  // ring of the last d commands, oldest at head_
  size_t head_ = 0;
};

/// \brief First-order servo lag 1 / (T s + 1), discretised exactly for an input held over each
/// sample: y <- y + (1 - exp(-dt/T)) (u - y). T = 0 is the pass-through (no lag).
class ServoLag {
 public:
  /// \brief Time constant T [s] >= 0 at sample time dt [s] > 0; the output starts at 0 rad.
  ServoLag(double time_constant = 0.0, double dt = 1.0);
  /// \brief The output at the end of a sample with input u [rad] held over it.
  double step(double u);
  void reset() { y_ = 0.0; }
  double output() const { return y_; }
  bool active() const { return active_; }

 private:
  bool active_ = false;
  double alpha_ = 1.0;  // 1 - exp(-dt/T)
  double y_ = 0.0;
};

/// \brief Command to deflection: delay, then lag, then the position and rate limits.
///
/// The limits act on the lagged signal and remember the last deflection they gave (their rate
/// limit is relative to it). limited() says whether they changed this sample's signal: that is
/// the plant's saturation count, which stays right with delay and lag on, where comparing the
/// deflection with the command would count every sample in which the servo is still moving.
class ActuatorChain {
 public:
  ActuatorChain(const ActuatorDynamics& dyn, const ActuatorLimits& limits, double dt);
  /// \brief The elevator deflection [rad] held over this sample, for command u [rad]. The
  /// paper's instant elevator (no delay, lag or limits) is answered here, inline: the plant's
  /// step costs what it cost before the chain existed.
  double apply(double u) {
    if (!identity_) return applyChain(u);
    applied_ = u;
    return u;
  }
  void reset();
  /// \brief The limits changed this sample's (delayed, lagged) signal.
  bool limited() const { return limited_; }
  /// \brief The last deflection [rad] (0 before the first sample).
  double applied() const { return applied_; }
  /// \brief True when the chain is the identity (no delay, no lag, no limits).
  bool identity() const { return identity_; }

 private:
  double applyChain(double u);
  TransportDelay delay_;
  ServoLag lag_;
  ActuatorLimits limits_;
  double dt_;
  bool identity_ = true;
  bool limited_ = false;
  double applied_ = 0.0;
};

}  // namespace preadaptive_mrac
