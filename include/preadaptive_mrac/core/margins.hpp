#pragma once
/// \file margins.hpp
/// \brief Robustness margins of a closed loop, measured by simulation: the time-delay margin
/// (the largest plant.actuator.delay) and the gain margins (the smallest and the largest
/// constant elevator effectiveness Lambda) at which the run stays within a bound.

#include <functional>
#include <limits>
#include <memory>
#include <string>

#include "preadaptive_mrac/core/closed_loop.hpp"

namespace preadaptive_mrac {

/// \brief What a margin search looks for and where.
struct MarginOptions {
  double bound = 0.2;      ///< "stable": every window's peak |e| <= bound [rad], all finite
  double max_delay = 2.0;  ///< top of the delay interval [0, max_delay] [s]
  double delay_resolution = 0.004;         ///< bisection stops at this bracket width [s]
  double min_effectiveness = 0.01;         ///< bottom of the lower gain interval [min, 1]
  double max_effectiveness = 2.0;          ///< top of the upper gain interval [1, max] (<= 2)
  double effectiveness_resolution = 0.01;  ///< bisection bracket width for Lambda
};

/// \brief One bisection: the largest (or smallest) value found stable and its unstable
/// neighbour, `resolution` apart unless the search did not bracket.
struct MarginSearch {
  /// "bracketed": the boundary lies in (stable, unstable] (or [unstable, stable) for the lower
  /// gain margin); "stable_at_limit": the criterion still held at the end of the interval
  /// (the margin is at least `stable`, `unstable` is NaN); "unstable_at_nominal": the nominal
  /// run already fails, nothing was searched (both NaN).
  std::string status;
  double stable = std::numeric_limits<double>::quiet_NaN();
  double unstable = std::numeric_limits<double>::quiet_NaN();
  int runs = 0;  ///< closed-loop runs of this search
};

/// \brief The margins of one configuration and the nominal run they start from.
struct MarginsResult {
  bool nominal_stable = false;
  RunMetrics nominal;  ///< the configuration as given (whole run unless it broke the bound)
  MarginSearch delay;  ///< [s], Lambda as configured
  MarginSearch effectiveness_low;   ///< smallest constant Lambda, delay as configured
  MarginSearch effectiveness_high;  ///< largest constant Lambda, delay as configured
  int runs = 0;
};

/// \brief A fresh controller for each run (the same initial state every time).
using ControllerFactory = std::function<std::unique_ptr<Controller>()>;

/// \brief One run, stopped at the first sample with |e| > bound or anything not finite.
/// Returns true when it went to the end within the bound; `metrics` gets its metrics.
bool runWithinBound(const PlantConfig& plant, const Scenario& scenario, double dt,
                    const ControllerFactory& make, double bound, RunMetrics* metrics = nullptr);

/// \brief Search the margins by bisection (delay in whole samples of dt [s]).
///
/// Delay: [0, max_delay], the plant's delay replaced; bisection on whole samples until the
/// stable and unstable delays are at most delay_resolution apart. Gain margins: the scenario's
/// effectiveness replaced by a constant Lambda, bisected on [min_effectiveness, 1] and
/// [1, max_effectiveness]. Bisection assumes one boundary in each interval (stable below the
/// delay margin, between the gain margins); the result is the bracket it found.
MarginsResult findMargins(const PlantConfig& plant, const Scenario& scenario, double dt,
                          const ControllerFactory& make, const MarginOptions& opt = {});

}  // namespace preadaptive_mrac
