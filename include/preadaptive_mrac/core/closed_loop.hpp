#pragma once
/// \file closed_loop.hpp
/// \brief Plant + controller composed for batch runs, and the metrics of docs/spec.md.

#include <string>
#include <vector>

#include "preadaptive_mrac/core/controller.hpp"
#include "preadaptive_mrac/core/plant.hpp"
#include "preadaptive_mrac/core/scenario.hpp"

namespace preadaptive_mrac {

/// \brief Metrics of one window between consecutive theta switches.
struct WindowMetrics {
  double t_start = 0.0, t_end = 0.0;
  Eigen::VectorXd theta;        ///< true theta in the window
  double peak_abs_e = 0.0;      ///< max |e| [rad]
  double iae = 0.0;             ///< integral |e| dt [rad s]
  double recovery_time = -1.0;  ///< switch to first RECOVERED event [s]; < 0 when none
  int onsets = 0, recoveries = 0;
};

/// \brief Whole-run metrics.
struct RunMetrics {
  std::vector<WindowMetrics> windows;
  double iae = 0.0, peak_abs_e = 0.0, max_abs_u = 0.0;
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
  const RunMetrics& metrics() const { return m_; }

 private:
  int windowOf(double t);
  RunMetrics m_;
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
};

/// \brief A plant driven by a scenario, one sample at a time: what the batch loop and the ROS
/// plant node both step, so that the two agree to the last bit.
///
/// Sample k is at t_k = k dt. Before advance(): state() is x_k, reference() is r(t_k) and
/// theta() is theta(t_k + dt/2), the value held over [t_k, t_k + dt]. advance(u) integrates
/// one RK4 step with u, r, theta held and moves to k + 1. done() once t_k >= t_end.
class ScenarioPlant {
 public:
  ScenarioPlant(const PlantConfig& plant, const Scenario& scenario, double dt);
  void reset();
  std::int64_t step() const { return k_; }
  std::int64_t totalSteps() const { return steps_; }
  double time() const { return static_cast<double>(k_) * dt_; }
  double dt() const { return dt_; }
  bool done() const { return k_ >= steps_; }
  /// \brief True state x_k.
  const Vec& state() const { return plant_.state(); }
  /// \brief What a sensor reports at t_k: x_k plus the configured noise (x_k when none).
  const Vec& measured() const { return measured_; }
  double reference() const { return r_; }
  const Vec& theta() const { return theta_; }
  /// \brief Integrate [t_k, t_k + dt] with elevator u [rad] held, after the actuator limits.
  void advance(double u);
  /// \brief Elevator actually applied over the last step [rad].
  double lastApplied() const { return u_applied_; }
  const Plant& plant() const { return plant_; }
  const Scenario& scenario() const { return scenario_; }

 private:
  void sampleInputs();
  Plant plant_;
  Scenario scenario_;
  double dt_;
  std::int64_t k_ = 0, steps_ = 0;
  double r_ = 0.0;
  Vec theta_;
  ActuatorLimits limits_;
  MeasurementNoise noise_cfg_;
  bool noisy_ = false;  // noise_cfg_.active(), once
  GaussianSource noise_;
  Vec measured_;
  double u_applied_ = 0.0;
  size_t theta_idx_ = 0, r_idx_ = 0;  // segments of the current sample (time only moves on)
};

/// \brief Options of a batch run.
struct SimOptions {
  double dt = 0.001;  ///< sample time = integration step [s]
  bool record_series = false;
};

/// \brief Result of a batch run.
struct SimResult {
  std::vector<Event> events;
  RunMetrics metrics;
  Series series;
  std::int64_t steps = 0;
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
