#pragma once
/// \file scenario.hpp
/// \brief Piecewise-constant schedules of theta(t) and r(t) (config/scenarios/*.yaml).

#include <array>
#include <string>
#include <vector>

#include "preadaptive_mrac/core/types.hpp"
#include "preadaptive_mrac/params/scenario_params.hpp"

namespace preadaptive_mrac {

class ParamReader;

/// \brief A scenario: theta and r as lists of segments, each holding its value until `until`.
///
/// A segment holds on (previous until, until]: theta changes right after the listed time,
/// as in the paper's eqs. theta-scenario-1/2/3. The last segment's `until` is the end time.
/// Its name and description are the struct generated from params/scenario.yaml.
struct Scenario : ScenarioParams {
  struct ThetaSegment {
    double until;
    Eigen::VectorXd theta;
  };
  struct RefSegment {
    double until;
    double r;
  };
  /// \brief Elevator effectiveness Lambda over (previous until, until] (in (0, 2]).
  struct EffectivenessSegment {
    double until;
    double value;
  };
  /// \brief Physical faults of a six-degree-of-freedom plant (plant.engine jsbsim) over
  /// (previous until, until]: centre-of-gravity shift, loss of elevator effectiveness in the
  /// aerodynamics, loss of pitch damping (PhysicalFaults; nominal where a key is left out).
  struct FaultSegment {
    double until;
    double cg_shift = 0.0, elevator_effectiveness = 1.0, pitch_damping = 1.0;
  };
  /// \brief One key of a fault segment: its name, its allowed range [lo, hi], its field and
  /// what it is (the reader's message); nominal = the field's default.
  struct FaultKey {
    const char* name;
    double lo, hi;
    double FaultSegment::*field;
    const char* what;
  };
  /// The fault keys in a fixed order (read by Scenario::read, drawn by preadapt_family --faults).
  static const std::array<FaultKey, 3> kFaultKeys;
  std::vector<ThetaSegment> theta;
  std::vector<RefSegment> reference;
  /// Elevator effectiveness schedule (key `effectiveness`); empty = Lambda 1 throughout.
  std::vector<EffectivenessSegment> effectiveness;
  /// Physical fault schedule (key `faults`); empty = the nominal aircraft throughout.
  std::vector<FaultSegment> faults;

  /// \brief End time [s] (the last theta segment's until).
  double endTime() const;
  /// \brief theta at time t [s] (the segment with previous until < t <= until).
  const Eigen::VectorXd& thetaAt(double t) const;
  /// \brief r at time t [rad].
  double rAt(double t) const;
  /// \brief Index of the theta segment thetaAt(t) returns, searched from `from` on: the same
  /// answer as long as `from` is the index returned for an earlier time (or 0), whatever the
  /// segments (no segment before it matched the earlier time, so none matches a later one).
  /// Lets a run that only moves forward in time find the segment without rescanning.
  size_t thetaIndexFrom(double t, size_t from) const;
  /// \brief The same for the reference segments (rAt).
  size_t rIndexFrom(double t, size_t from) const;
  /// \brief The same for the effectiveness segments (callers check it is not empty).
  size_t effectivenessIndexFrom(double t, size_t from) const;
  /// \brief The same for the fault segments (callers check it is not empty).
  size_t faultIndexFrom(double t, size_t from) const;
  /// \brief Elevator effectiveness Lambda at time t [s] (1 without a schedule).
  double effectivenessAt(double t) const;
  /// \brief Times where theta changes (every until but the last).
  std::vector<double> switchTimes() const;

  /// \brief Read the `scenario` section for a plant of n states (0: unknown, the plant was refused;
  /// theta vectors of any size, so the plant's problem is not echoed as a scenario one).
  /// Segments: {until: s, scale: c} (theta = c * ones) or {until: s, theta: [..]};
  /// reference: {until: s, r: value}; a missing `reference` means r = 0.1 rad throughout;
  /// effectiveness (optional): {until: s, value: Lambda}, Lambda in (0, 2], reaching the end.
  static Scenario read(ParamReader& r, int n, const std::string& prefix = "scenario");
};

}  // namespace preadaptive_mrac
