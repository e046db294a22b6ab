#include "preadaptive_mrac/core/margins.hpp"

#include <cmath>

#include "preadaptive_mrac/core/sim/actuator.hpp"

namespace preadaptive_mrac {

bool runWithinBound(const PlantConfig& plant, const Scenario& scenario, double dt,
                    const ControllerFactory& make, double bound, RunMetrics* metrics) {
  std::unique_ptr<Controller> ctl = make();
  ClosedLoop loop(plant, scenario, ctl.get());
  SimOptions opt;
  opt.dt = dt;
  opt.stop_above = bound;
  const SimResult res = loop.run(opt);
  if (metrics) *metrics = res.metrics;
  return !res.stopped && std::isfinite(res.metrics.iae) && res.metrics.peak_abs_e <= bound;
}

namespace {
// Bisection between a stable and an unstable value of a parameter (either order); `stable_at`
// runs the closed loop at a value. `done(a, b)` says when the bracket is narrow enough, `mid`
// picks the next value (whole samples for the delay).
template <typename T, typename Stable, typename Done, typename Mid>
MarginSearch bisect(T nominal, T limit, Stable stable_at, Done done, Mid mid) {
  MarginSearch s;
  ++s.runs;
  if (stable_at(limit)) {
    s.status = "stable_at_limit";
    s.stable = static_cast<double>(limit);
    return s;
  }
  T good = nominal, bad = limit;
  while (!done(good, bad)) {
    const T m = mid(good, bad);
    ++s.runs;
    (stable_at(m) ? good : bad) = m;
  }
  s.status = "bracketed";
  s.stable = static_cast<double>(good);
  s.unstable = static_cast<double>(bad);
  return s;
}

MarginSearch unstableAtNominal() {
  MarginSearch s;
  s.status = "unstable_at_nominal";
  return s;
}
}  // namespace

MarginsResult findMargins(const PlantConfig& plant, const Scenario& scenario, double dt,
                          const ControllerFactory& make, const MarginOptions& opt) {
  MarginsResult out;
  out.nominal_stable = runWithinBound(plant, scenario, dt, make, opt.bound, &out.nominal);
  out.runs = 1;
  if (!out.nominal_stable) {
    out.delay = out.effectiveness_low = out.effectiveness_high = unstableAtNominal();
    return out;
  }
  // Delay in whole samples: the plant rounds delay / dt, so search the integers it can take.
  // The search starts from delay 0, which must be stable (it is the nominal run unless the
  // plant has a delay already).
  PlantConfig delayed = plant;
  delayed.dynamics.delay = 0.0;
  const bool zero_delay_stable =
      plant.dynamics.delay == 0.0 || runWithinBound(delayed, scenario, dt, make, opt.bound);
  const std::int64_t res_steps =
      std::max<std::int64_t>(1, TransportDelay::stepsFor(opt.delay_resolution, dt));
  out.delay =
      !zero_delay_stable
          ? unstableAtNominal()
          : bisect<std::int64_t>(
                0, TransportDelay::stepsFor(opt.max_delay, dt),
                [&](std::int64_t d) {
                  delayed.dynamics.delay = static_cast<double>(d) * dt;
                  return runWithinBound(delayed, scenario, dt, make, opt.bound);
                },
                [&](std::int64_t a, std::int64_t b) { return std::abs(b - a) <= res_steps; },
                [](std::int64_t a, std::int64_t b) { return a + (b - a) / 2; });
  out.delay.stable *= dt;
  out.delay.unstable *= dt;
  // Gain margins: a constant Lambda over the whole run.
  Scenario scaled = scenario;
  const auto stable_lambda = [&](double lambda) {
    scaled.effectiveness = {{scenario.endTime(), lambda}};
    return runWithinBound(plant, scaled, dt, make, opt.bound);
  };
  const auto narrow = [&](double a, double b) {
    return std::abs(b - a) <= opt.effectiveness_resolution * (1.0 + 1e-9);
  };
  const auto half = [](double a, double b) { return 0.5 * (a + b); };
  // Likewise Lambda = 1 (the nominal run unless the scenario schedules Lambda).
  if (scenario.effectiveness.empty() || stable_lambda(1.0)) {
    out.effectiveness_low = bisect<double>(1.0, opt.min_effectiveness, stable_lambda, narrow, half);
    out.effectiveness_high =
        bisect<double>(1.0, opt.max_effectiveness, stable_lambda, narrow, half);
  } else {
    out.effectiveness_low = out.effectiveness_high = unstableAtNominal();
  }
  out.runs += out.delay.runs + out.effectiveness_low.runs + out.effectiveness_high.runs;
  return out;
}

}  // namespace preadaptive_mrac
