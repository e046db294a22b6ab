#pragma once
/// \file scenario_plant.hpp
/// \brief The plant simulator: the plant driven by a scenario, with the actuator chain
/// (delay, lag, limits), the elevator effectiveness and Dryden turbulence applied to it.

#include <cstdint>
#include <memory>

#include "preadaptive_mrac/core/sim/actuator.hpp"
#include "preadaptive_mrac/core/sim/envelope.hpp"
#include "preadaptive_mrac/core/sim/plant.hpp"
#include "preadaptive_mrac/core/sim/plant_conditions.hpp"
#include "preadaptive_mrac/core/sim/plant_engine.hpp"
#include "preadaptive_mrac/core/sim/scenario.hpp"
#include "preadaptive_mrac/core/sim/turbulence.hpp"

namespace preadaptive_mrac {

/// \brief A plant driven by a scenario, one sample at a time: what the batch loop and the ROS
/// plant node both step, so that the two agree to the last bit.
///
/// Sample k is at t_k = k dt. Before advance(): state() is x_k, reference() is r(t_k),
/// theta() and effectiveness() are the scenario's values at t_k + dt/2 (held over
/// [t_k, t_k + dt]) and gust() is w_g(t_k), held over the sample too. advance(u) passes the
/// command u through the actuator chain (delay, lag, limits), integrates one RK4 step of
///   x_dot = A x + B (theta^T x + Lambda u_applied) + B1r r + g alpha_g,  alpha_g = w_g / V,
/// with g the alpha column of A in every row but the tracking-error integrator's (the rows
/// where B1r is 0: the integrator integrates the measured alpha), and moves to k + 1.
/// done() once t_k >= t_end. The controller is told none of this.
///
/// With plant.engine jsbsim a PlantEngine (JSBSim, trimmed) integrates instead of the linear
/// model: the same actuator chain, Lambda, theta, noise and gust, the gust as a vertical wind
/// (PlantEngine::step); A, B, B1r are then only the controller's model.
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
  const Vec& state() const { return engine_ ? engine_->state() : plant_.state(); }
  /// \brief Pitch attitude, airspeed, altitude, flight path angle at t_k: nullptr on the
  /// linear plant (also the engine rows of conditions()).
  const FlightOutputs* flight() const { return engine_ ? &engine_->flight() : nullptr; }
  /// \brief The engine (nullptr on the linear plant).
  PlantEngine* engine() const { return engine_.get(); }
  /// \brief The run is over: end the engine's process now (PlantEngine::close) rather than
  /// when this object goes; nothing may advance() or reset() after it.
  void closeEngine() {
    if (engine_) engine_->close();
  }
  /// \brief What a sensor reports at t_k: x_k plus the configured noise (x_k when none).
  const Vec& measured() const { return measured_; }
  double reference() const { return r_; }
  const Vec& theta() const { return theta_; }
  /// \brief The conditions record at t_k (plant_conditions.hpp): the values held over the
  /// coming step, what the last step did (its applied elevator and limit flag; 0 before
  /// the first step), and on an engine its flight outputs at t_k.
  const PlantConditions& conditions() const { return cond_; }
  /// \brief The rows of the record this plant has: the plant's when hasConditions(), the
  /// engine's on an engine.
  ConditionRows conditionRows() const { return {conditions_, engine_ != nullptr}; }
  /// \brief Elevator effectiveness Lambda held over the coming step (1 without a schedule).
  double effectiveness() const { return cond_.effectiveness; }
  /// \brief Vertical gust w_g [m/s] held over the coming step (0 without turbulence).
  double gust() const { return cond_.w_gust; }
  /// \brief The angle-of-attack disturbance alpha_g = w_g / V [rad] of the coming step.
  double gustAlpha() const { return gust_.value() * inv_airspeed_; }
  /// \brief Integrate [t_k, t_k + dt] with the elevator command u [rad] through the actuator
  /// chain.
  void advance(double u);
  /// \brief Elevator deflection applied over the last step [rad]: the command after delay, lag
  /// and limits, before the effectiveness Lambda (the surface's angle, not its effect).
  double lastApplied() const { return cond_.u_applied; }
  /// \brief The command given to the last advance() [rad].
  double lastCommand() const { return u_cmd_; }
  /// \brief The limits changed the (delayed, lagged) command of the last step.
  bool lastLimited() const { return cond_.plant_limited != 0.0; }
  /// \brief Steps since reset() in which the limits changed the signal (the saturation count).
  std::int64_t limitedSteps() const { return limited_steps_; }
  /// \brief Delay, lag, an effectiveness schedule or turbulence are configured (the paper's
  /// ideal plant otherwise, limits or not).
  bool hasConditions() const { return conditions_; }
  /// \brief The first exit from the flight envelope (plant.envelope) since reset(): the
  /// command given to advance() is checked at t_k, the state reached at t_k + dt.
  const EnvelopeExit& envelopeExit() const { return envelope_.exit(); }
  /// \brief A state or command was not finite: nothing after it means anything, end the run.
  bool nonFinite() const { return envelope_.nonFinite(); }
  const Plant& plant() const { return plant_; }
  const Scenario& scenario() const { return scenario_; }

 private:
  void sampleInputs();
  Plant plant_;
  std::unique_ptr<PlantEngine> engine_;  // plant.engine other than linear
  Scenario scenario_;
  double dt_;
  std::int64_t k_ = 0, steps_ = 0;
  double r_ = 0.0;
  Vec theta_;
  ActuatorChain actuator_;
  DrydenGust gust_;
  Vec gust_col_, disturbance_;  // g, and g alpha_g of the current step
  double inv_airspeed_ = 0.0;
  bool has_lambda_ = false;  // the scenario schedules Lambda
  PlantConditions cond_;
  EnvelopeMonitor envelope_;
  bool conditions_ = false;
  MeasurementNoise noise_cfg_;
  bool noisy_ = false;  // noise_cfg_.active(), once
  GaussianSource noise_;
  Vec measured_;
  double u_cmd_ = 0.0;
  std::int64_t limited_steps_ = 0;
  size_t theta_idx_ = 0, r_idx_ = 0, lambda_idx_ = 0;  // segments of the current sample
  size_t fault_idx_ = 0;
};

}  // namespace preadaptive_mrac
