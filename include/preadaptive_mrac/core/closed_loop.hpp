#pragma once
/// \file closed_loop.hpp
/// \brief Plant + controller composed for batch runs, and the metrics of docs/spec.md.

#include <limits>
#include <string>
#include <vector>

#include "preadaptive_mrac/core/controller/controller.hpp"
#include "preadaptive_mrac/core/sim/plant.hpp"
#include "preadaptive_mrac/core/sim/scenario.hpp"
#include "preadaptive_mrac/core/sim/scenario_plant.hpp"

namespace preadaptive_mrac {

/// \brief The plant as the controller knows it: the plant's A, B, B1r, x0, output and elevator
/// limits, with A, B and B1r replaced by those `cfg.model` (`controller.model`) gives. The one
/// place where the simulator's configuration meets the controller's: the controller itself
/// never sees the PlantConfig (its noise, turbulence, servo dynamics or engine).
DesignModel designModelOf(const PlantConfig& plant, const ControllerConfig& cfg);

/// \brief Metrics of one window between consecutive theta switches.
struct WindowMetrics {
  double t_start = 0.0, t_end = 0.0;
  Eigen::VectorXd theta;        ///< true theta in the window
  double peak_abs_e = 0.0;      ///< max |e| [rad]
  double iae = 0.0;             ///< integral |e| dt [rad s]
  double recovery_time = -1.0;  ///< switch to first RECOVERED event [s]; < 0 when none
  int onsets = 0, recoveries = 0;
  double time_at_limit = 0.0;  ///< applied elevator at its travel or rate limit [s]
  double steady_tv = 0.0;      ///< applied elevator's total variation over the steady part [rad]
};

/// \brief Elevator effort of a run: the elevator the plant applied (after the servo's delay,
/// lag and limits), not the command.
struct EffortMetrics {
  /// The steady part of a window: its last kSteadyFraction (after the switch's transient).
  static constexpr double kSteadyFraction = 0.5;
  double peak_abs_u = 0.0;      ///< max |applied| [rad]
  double time_at_travel = 0.0;  ///< |applied| at plant.actuator.max_deflection [s]
  double time_at_rate = 0.0;    ///< |step change| at plant.actuator.max_rate dt [s]
  /// Total variation sum |u_k - u_{k-1}| of the applied elevator over the steady part of every
  /// window, summed [rad] (steady-flight buzz: 0 for a still elevator).
  double steady_tv = 0.0;
};

/// \brief Whole-run metrics.
struct RunMetrics {
  std::vector<WindowMetrics> windows;
  double iae = 0.0, peak_abs_e = 0.0, max_abs_u = 0.0;
  EffortMetrics effort;
};

/// \brief Accumulates metrics sample by sample; used by the batch loop and by bag analysis.
class MetricsAccumulator {
 public:
  /// \brief Windows start at 0 and at each switch time; the last ends at t_end.
  MetricsAccumulator(const std::vector<double>& switch_times, double t_end,
                     const std::vector<Eigen::VectorXd>& window_theta);
  /// \brief One sample at t (held for dt) with error e and command u.
  void add(double t, double dt, double e, double u);
  void addEvent(const Event& ev);
  /// \brief The elevator's limits, for the time at them (none when disabled).
  void setLimits(const ActuatorLimits& limits) { limits_ = limits; }
  /// \brief The elevator applied over [t, t + dt] (the sample after add(t, ...)); the first
  /// sample's change is from 0, the actuator's rest.
  void addApplied(double t, double dt, double u_applied);
  const RunMetrics& metrics() const { return m_; }

 private:
  int windowOf(double t);
  RunMetrics m_;
  ActuatorLimits limits_;
  double prev_applied_ = 0.0;
  int prev_steady_window_ = -1;  ///< the window whose steady part held the previous sample
  // The window of the last look-up and its time: a later time searches on from there (the
  // same answer as a search from the first window; runs move forward in time).
  double hint_t_ = 0.0;
  size_t hint_ = 0;
};

/// \brief Time series of a run (one row per sample).
struct Series {
  std::vector<double> t, e, e_dot, u, u_bl, u_ad, r;
  std::vector<Vec> x, x_r, theta_hat, theta_true;  ///< x: true state
  std::vector<int> phase, saturated;
  /// The plant's conditions over each step (core/sim/plant_conditions.hpp), recorded only when
  /// it has some: the rows of condition_rows (the plant's when ScenarioPlant::hasConditions;
  /// on an engine, plant.engine jsbsim, its flight outputs at t_k: pitch attitude, airspeed,
  /// altitude, flight path angle). Empty for the paper's ideal linear plant.
  std::vector<PlantConditions> conditions;
  ConditionRows condition_rows;
};

/// \brief Options of a batch run.
struct SimOptions {
  double dt = 0.001;  ///< sample time = integration step [s]
  bool record_series = false;
  /// Stop the run at the first sample with |e| above this [rad] or anything not finite (a
  /// margin search needs only to know that the bound was broken); infinity: never.
  double stop_above = std::numeric_limits<double>::infinity();
};

/// \brief Result of a batch run.
struct SimResult {
  std::vector<Event> events;
  RunMetrics metrics;
  Series series;
  std::int64_t steps = 0;                ///< samples run (fewer than the scenario's when stopped)
  bool stopped = false;                  ///< stopped early by SimOptions::stop_above
  std::int64_t plant_limited_steps = 0;  ///< steps the plant's limits changed the signal
  /// The first exit from the plant's flight envelope (exited false: the run stayed inside). A
  /// state or command that is not finite ends the run at that step (non_finite).
  EnvelopeExit envelope_exit;
};

/// \brief The closed loop of a plant, a scenario and a controller.
///
/// Sample k at t_k = k dt: the controller sees x_k and r(t_k) and returns u_k; the plant then
/// integrates over [t_k, t_k + dt] with u_k, r and theta(t_k + dt/2) held (RK4). The run covers
/// t_k < t_end.
class ClosedLoop {
 public:
  ClosedLoop(const PlantConfig& plant, const Scenario& scenario, Controller* controller);
  SimResult run(const SimOptions& opt);

 private:
  PlantConfig plant_cfg_;
  const Scenario& scenario_;
  Controller* ctl_;
};

}  // namespace preadaptive_mrac
