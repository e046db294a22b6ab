#include "preadaptive_mrac/core/closed_loop.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "preadaptive_mrac/core/small_ops.hpp"

namespace preadaptive_mrac {

DesignModel designModelOf(const PlantConfig& plant, const ControllerConfig& cfg) {
  DesignModel m;
  m.A = plant.A;
  m.B = plant.B;
  m.B1r = plant.B1r;
  m.x0 = plant.x0;
  m.output_index = plant.output_index;
  m.limits = plant.actuator.elevator();
  return cfg.model.over(std::move(m));
}

MetricsAccumulator::MetricsAccumulator(const std::vector<double>& switch_times, double t_end,
                                       const std::vector<Eigen::VectorXd>& window_theta) {
  double start = 0.0;
  for (size_t i = 0; i <= switch_times.size(); ++i) {
    WindowMetrics w;
    w.t_start = start;
    w.t_end = i < switch_times.size() ? switch_times[i] : t_end;
    if (i < window_theta.size()) w.theta = window_theta[i];
    m_.windows.push_back(w);
    start = w.t_end;
  }
}

int MetricsAccumulator::windowOf(double t) {
  // A window holds (t_start, t_end]: the sample exactly at a switch still belongs to the old
  // theta, matching the scenario's segments. Sample 0 belongs to the first window.
  // The first window with t <= t_end: no window before the one found for an earlier time
  // holds a later one, so a later time searches on from there.
  size_t i = t >= hint_t_ ? hint_ : 0;
  while (i < m_.windows.size() && !(t <= m_.windows[i].t_end)) ++i;
  if (i == m_.windows.size()) return static_cast<int>(m_.windows.size()) - 1;
  hint_t_ = t;
  hint_ = i;
  return static_cast<int>(i);
}

void MetricsAccumulator::add(double t, double dt, double e, double u) {
  WindowMetrics& w = m_.windows[static_cast<size_t>(windowOf(t))];
  const double a = std::abs(e);
  w.peak_abs_e = std::max(w.peak_abs_e, a);
  w.iae += a * dt;
  m_.iae += a * dt;
  m_.peak_abs_e = std::max(m_.peak_abs_e, a);
  m_.max_abs_u = std::max(m_.max_abs_u, std::abs(u));
}

void MetricsAccumulator::addApplied(double t, double dt, double u_applied) {
  const int wi = windowOf(t);
  WindowMetrics& w = m_.windows[static_cast<size_t>(wi)];
  EffortMetrics& f = m_.effort;
  const double a = std::abs(u_applied), step = std::abs(u_applied - prev_applied_);
  f.peak_abs_u = std::max(f.peak_abs_u, a);
  // At a limit within rounding: the limiter returns the limit itself (or u_prev + max_rate dt).
  constexpr double kTol = 1e-9;
  const bool travel = limits_.enabled && a >= limits_.max_deflection * (1.0 - kTol);
  const bool rate = limits_.enabled && step >= limits_.max_rate * dt * (1.0 - kTol);
  if (travel) f.time_at_travel += dt;
  if (rate) f.time_at_rate += dt;
  if (travel || rate) w.time_at_limit += dt;
  const bool steady =
      t >= w.t_end - EffortMetrics::kSteadyFraction * (w.t_end - w.t_start) - 0.5 * dt;
  if (steady && prev_steady_window_ == wi) {
    w.steady_tv += step;
    f.steady_tv += step;
  }
  prev_steady_window_ = steady ? wi : -1;
  prev_applied_ = u_applied;
}

void MetricsAccumulator::addEvent(const Event& ev) {
  WindowMetrics& w = m_.windows[static_cast<size_t>(windowOf(ev.t))];
  if (ev.type == Event::Type::kOnset) ++w.onsets;
  if (ev.type == Event::Type::kRecovered) {
    ++w.recoveries;
    if (w.recovery_time < 0.0) w.recovery_time = ev.t - w.t_start;
  }
}

ClosedLoop::ClosedLoop(const PlantConfig& plant, const Scenario& scenario, Controller* controller)
    : plant_cfg_(plant), scenario_(scenario), ctl_(controller) {}

SimResult ClosedLoop::run(const SimOptions& opt) {
  SimResult res;
  ScenarioPlant sim(plant_cfg_, scenario_, opt.dt);
  const double dt = opt.dt;
  std::vector<Eigen::VectorXd> wtheta;
  for (const auto& s : scenario_.theta) wtheta.push_back(s.theta);
  MetricsAccumulator acc(scenario_.switchTimes(), scenario_.endTime(), wtheta);
  acc.setLimits(plant_cfg_.actuator);
  ctl_->reset();
  const std::int64_t steps = sim.totalSteps();
  if (opt.record_series) {
    auto& s = res.series;
    for (auto* v : {&s.t, &s.e, &s.e_dot, &s.u, &s.u_bl, &s.u_ad, &s.r})
      v->reserve(static_cast<size_t>(steps));
    for (auto* v : {&s.x, &s.x_r, &s.theta_hat, &s.theta_true})
      v->reserve(static_cast<size_t>(steps));
    s.phase.reserve(static_cast<size_t>(steps));
    s.saturated.reserve(static_cast<size_t>(steps));
    if (sim.conditionRows().any()) s.conditions.reserve(static_cast<size_t>(steps));
    s.condition_rows = sim.conditionRows();
  }
  // The conditions' columns: what the plant did over each sample, recorded after advance().
  const bool conditions = opt.record_series && sim.conditionRows().any();
  const bool stopping = opt.stop_above < std::numeric_limits<double>::infinity();
  while (!sim.done()) {
    const double t = sim.time();
    PlantConditions before;  // held over this step (copied only when recorded)
    if (conditions) before = sim.conditions();
    StepInput in;
    in.t = t;
    in.x = &sim.measured();  // unchanged until sim.advance()
    in.r = sim.reference();
    in.theta_true = &sim.theta();
    const double u_applied = sim.lastApplied();
    in.u_applied = &u_applied;
    const StepOutput o = ctl_->step(in);
    if (o.event) {
      acc.addEvent(*o.event);
      res.events.push_back(*o.event);
    }
    acc.add(t, dt, o.e, o.u);
    if (opt.record_series) {
      auto& s = res.series;
      s.t.push_back(t);
      s.e.push_back(o.e);
      s.e_dot.push_back(o.e_dot);
      s.u.push_back(o.u);
      s.u_bl.push_back(o.u_baseline);
      s.u_ad.push_back(o.u_adaptive);
      s.r.push_back(in.r);
      s.x.push_back(sim.state());
      s.x_r.push_back(o.x_ref);
      s.theta_hat.push_back(o.theta_hat);
      s.theta_true.push_back(sim.theta());
      s.phase.push_back(ctl_->phaseActive() ? 1 : 0);
      s.saturated.push_back(o.saturated ? 1 : 0);
    }
    if (stopping && !(std::abs(o.e) <= opt.stop_above && std::isfinite(o.u))) {
      res.stopped = true;
      break;
    }
    sim.advance(o.u);
    acc.addApplied(t, dt, sim.lastApplied());
    if (conditions) res.series.conditions.push_back(completeStep(before, sim.conditions()));
    if (sim.nonFinite()) break;  // nothing after a non-finite state means anything
  }
  res.steps = sim.step();
  res.plant_limited_steps = sim.limitedSteps();
  res.envelope_exit = sim.envelopeExit();
  res.metrics = acc.metrics();
  return res;
}

}  // namespace preadaptive_mrac
