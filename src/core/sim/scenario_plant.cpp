#include "preadaptive_mrac/core/sim/scenario_plant.hpp"

#include <cmath>
#include <stdexcept>

#include "preadaptive_mrac/core/small_ops.hpp"

namespace preadaptive_mrac {

ScenarioPlant::ScenarioPlant(const PlantConfig& plant, const Scenario& scenario, double dt)
    : plant_(plant),
      scenario_(scenario),
      dt_(dt),
      actuator_(plant.dynamics, plant.actuator, dt > 0.0 ? dt : 1.0),
      gust_(plant.turbulence, plant.airspeed, dt > 0.0 ? dt : 1.0),
      has_lambda_(!scenario.effectiveness.empty()),
      envelope_(plant.envelope, plant.output_index, plantEngineRules(plant.engine).flight_outputs),
      noise_cfg_(plant.noise),
      noisy_(plant.noise.active()),
      noise_(plant.noise.seed) {
  if (!(dt > 0.0)) throw std::invalid_argument("dt must be > 0");
  engine_ = makePlantEngine(plant, dt);
  // The gust filter's V on an engine is its trimmed airspeed (operating_point.U is the
  // linear model's).
  if (engine_ && gust_.active()) gust_ = DrydenGust(plant.turbulence, engine_->trimAirspeed(), dt);
  // Samples t_k = k dt with t_k < t_end (a tolerance guards against round-off in t_end / dt).
  steps_ = static_cast<std::int64_t>(std::ceil(scenario_.endTime() / dt_ - 1e-9));
  if (gust_.active() && !engine_) {
    inv_airspeed_ = 1.0 / plant.airspeed;
    gust_col_ = plant.A.col(plant.output_index);
    for (Eigen::Index i = 0; i < gust_col_.size(); ++i)
      if (plant.B1r[i] != 0.0) gust_col_[i] = 0.0;
    disturbance_.setZero(gust_col_.size());
  }
  conditions_ = plant.dynamics.delay > 0.0 || plant.dynamics.time_constant > 0.0 || has_lambda_ ||
                gust_.active();
  reset();
}

void ScenarioPlant::reset() {
  plant_.reset();
  if (engine_) engine_->reset();
  k_ = 0;
  u_cmd_ = 0.0;
  limited_steps_ = 0;
  actuator_.reset();
  gust_.reset();
  cond_ = PlantConditions();
  envelope_.reset();
  theta_idx_ = r_idx_ = lambda_idx_ = 0;
  fault_idx_ = 0;
  noise_.reseed(noise_cfg_.seed);
  sampleInputs();
}

void ScenarioPlant::sampleInputs() {
  const double t = time();
  // Scenario::rAt(t) and thetaAt(t + dt/2), searched on from the last sample's segments (t
  // only grows between resets); theta is copied when its segment changes.
  r_idx_ = scenario_.rIndexFrom(t, r_idx_);
  r_ = scenario_.reference[r_idx_].r;
  const double mid = t + 0.5 * dt_;
  const size_t ti = scenario_.thetaIndexFrom(mid, theta_idx_);
  if (k_ == 0 || ti != theta_idx_) theta_ = scenario_.theta[ti].theta;
  theta_idx_ = ti;
  if (has_lambda_) {
    lambda_idx_ = scenario_.effectivenessIndexFrom(mid, lambda_idx_);
    cond_.effectiveness = scenario_.effectiveness[lambda_idx_].value;
  }
  cond_.w_gust = gust_.value();
  if (engine_) {
    const FlightOutputs& f = engine_->flight();  // at t_k: the state's sample
    cond_.pitch = f.pitch;
    cond_.airspeed = f.airspeed;
    cond_.altitude = f.altitude;
    cond_.flight_path = f.flight_path;
  }
  if (engine_ && !scenario_.faults.empty()) {
    fault_idx_ = scenario_.faultIndexFrom(mid, fault_idx_);
    const auto& f = scenario_.faults[fault_idx_];
    engine_->setFaults({f.cg_shift, f.elevator_effectiveness, f.pitch_damping});
  }
  copyTo(state(), &measured_);
  if (noisy_)
    for (Eigen::Index i = 0; i < measured_.size(); ++i)
      measured_[i] += noise_cfg_.std[i] * noise_.next();
}

void ScenarioPlant::advance(double u) {
  u_cmd_ = u;
  envelope_.checkCommand(k_, time(), u, state(), cond_);
  const double applied = actuator_.apply(u);
  if (actuator_.limited()) ++limited_steps_;
  cond_.u_applied = applied;
  cond_.plant_limited = actuator_.limited() ? 1.0 : 0.0;
  // Without a schedule the applied deflection goes in as it is: the paper's bits.
  const double effect = has_lambda_ ? cond_.effectiveness * applied : applied;
  if (engine_) {
    engine_->step(dt_, theta_, effect, r_, gust_.active() ? gust_.value() : 0.0);
    if (gust_.active()) gust_.advance();
  } else if (gust_.active()) {
    disturbance_ = gustAlpha() * gust_col_;
    plant_.stepDisturbed(dt_, theta_, effect, r_, disturbance_);
    gust_.advance();
  } else {
    plant_.step(dt_, theta_, effect, r_);
  }
  ++k_;
  sampleInputs();
  envelope_.checkState(k_, time(), state(), u, cond_);
}

}  // namespace preadaptive_mrac
