// Saturation-aware adaptation (docs/research/saturation.md): with
// controller.adaptation.hedging none or without limits every mode runs as before; with pch and
// the limits known, the adaptive law does not integrate the error the limit caused; pa_robust's
// elevator dither runs only while it identifies a regime.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "preadaptive_mrac/core/closed_loop.hpp"
#include "preadaptive_mrac/core/controller/mode_registry.hpp"
#include "test_helpers.hpp"

using namespace preadaptive_mrac;

namespace {

bool sameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// The elevator's total variation sum |u_k - u_{k-1}| over [t0, t1] [rad].
double totalVariation(const Series& s, double t0, double t1) {
  double tv = 0.0;
  for (size_t k = 1; k < s.t.size(); ++k)
    if (s.t[k - 1] >= t0 && s.t[k] <= t1) tv += std::abs(s.u[k] - s.u[k - 1]);
  return tv;
}

RunConfig limited(const std::string& mode, Hedging h) {
  RunConfig cfg = test::packageConfig("1");
  cfg.controller.mode = mode;
  cfg.controller.hedging = h;
  cfg.plant.actuator.enabled = true;
  cfg.plant.actuator.max_deflection = 0.35;
  cfg.plant.actuator.max_rate = 0.65;
  return cfg;
}

}  // namespace

// Hedging changes nothing where nothing is limited: without limits, and with limits the
// command never reaches (bit for bit, every mode).
TEST(Saturation, HedgingChangesNothingWithoutALimit) {
  for (const std::string& mode : modeNameList()) {
    for (bool wide : {false, true}) {
      RunConfig off = test::packageConfig("1");
      off.controller.mode = mode;
      // Scenario 1 to 24 s: the switches at 5 and 20 s, in a few seconds of test.
      off.scenario.theta.resize(3);
      off.scenario.theta[2].until = 24.0;
      off.scenario.reference = {{24.0, 0.1}};
      if (wide) {
        off.plant.actuator.enabled = true;
        off.plant.actuator.max_deflection = 100.0;
        off.plant.actuator.max_rate = 1000.0;
      }
      RunConfig pch = off;
      pch.controller.hedging = Hedging::kPch;
      const SimResult a = test::simulate(off), b = test::simulate(pch);
      EXPECT_TRUE(sameBits(a.series.u, b.series.u)) << mode << (wide ? " wide limits" : "");
      EXPECT_TRUE(sameBits(a.series.e, b.series.e)) << mode << (wide ? " wide limits" : "");
    }
  }
}

// The limit's own part of the error is not adapted on. The estimate starts at the true theta,
// so a perfect law has nothing to learn; a step of the command drives the elevator into its
// travel and rate limits. Unhedged (freeze off), the law integrates the error the limit made
// and the estimate wanders off the truth; hedged, it stays there (up to the plant's sampling).
TEST(Saturation, HedgedLawDoesNotAdaptOnTheLimitsError) {
  for (const char* mode : {"rac", "l1"}) {
    auto drift = [&](Hedging h) {
      RunConfig cfg = limited(mode, h);
      cfg.controller.freeze_when_saturated = false;
      const Vec theta = Vec::Constant(3, 2.0);
      cfg.controller.theta_hat0 = theta;
      cfg.controller.l1.theta_max = 25.0;
      cfg.scenario.theta.clear();
      cfg.scenario.theta.push_back({8.0, theta});
      cfg.scenario.reference = {{1.0, 0.1}, {4.0, 0.4}, {8.0, -0.1}};
      Controller ctl(designModelOf(cfg.plant, cfg.controller), cfg.controller);
      ScenarioPlant plant(cfg.plant, cfg.scenario, cfg.controller.sample_time);
      double worst = 0.0;
      int limited_steps = 0;
      while (!plant.done()) {
        const StepOutput out = ctl.step(test::lockstepInput(plant, nullptr));
        limited_steps += out.saturated ? 1 : 0;
        worst = std::max(worst, (out.theta_hat - theta).norm());
        plant.advance(out.u);
      }
      EXPECT_GT(limited_steps, 100) << mode << ": the test must reach the limits";
      return worst;
    };
    const double unhedged = drift(Hedging::kNone), hedged = drift(Hedging::kPch);
    EXPECT_GT(unhedged, 0.2) << mode;
    EXPECT_LT(hedged, 0.1 * unhedged) << mode << ": unhedged " << unhedged;
  }
}

// pa_robust's square wave: by default (the package's config, and a config without the key) it
// probes the elevator after an onset and is off in steady flight (scenario 1, 30-44 s: at most
// twice rac's total variation); with excitation_time 0 it runs all the time (about ten times
// rac's). Saturation-aware adaptation is on by default too.
TEST(Saturation, DitherIsOffInSteadyFlightByDefault) {
  EXPECT_GT(RobustConfig{}.excitation_time, 0.0);
  EXPECT_EQ(ControllerConfig{}.hedging, Hedging::kPch);
  RunConfig cfg = test::packageConfig("1");
  EXPECT_EQ(cfg.controller.hedging, Hedging::kPch);
  cfg.controller.mode = "rac";
  const double rac = totalVariation(test::simulate(cfg).series, 30.0, 44.0);
  cfg.controller.mode = "pa_robust";
  const SimResult episodic = test::simulate(cfg);
  cfg.controller.robust.excitation_time = 0.0;
  const double always = totalVariation(test::simulate(cfg).series, 30.0, 44.0);
  EXPECT_GT(always, 5.0 * rac);
  EXPECT_LE(totalVariation(episodic.series, 30.0, 44.0), 2.0 * rac);
  // It still probes right after the switch at 20 s (onset within a few samples).
  EXPECT_GT(totalVariation(episodic.series, 20.5, 22.5), 2.0 * 0.002 * 3.0);
}

// pa_robust's error feedback in steady flight under sensor noise (the families' setting: the
// limited elevator, servo lag 0.05 s, 0.1 mrad on alpha and q; scenario 1, 30-44 s): on the
// low-passed error (the default) the elevator's total variation is at most twice rac's; on the
// error itself all the time (feedback_time 0) the elevator answers the noise, more than twice.
TEST(Saturation, ErrorFeedbackDoesNotAnswerTheNoiseInSteadyFlight) {
  EXPECT_GT(RobustConfig{}.feedback_time, 0.0);
  EXPECT_GT(RobustConfig{}.steady_filter, 0.0);
  auto tv = [](const std::string& mode, double feedback_time) {
    RunConfig cfg = limited(mode, Hedging::kPch);
    cfg.plant.dynamics.time_constant = 0.05;
    cfg.plant.noise.std = Vec::Constant(3, 1e-4);
    cfg.plant.noise.std[0] = 0.0;
    cfg.plant.noise.seed = 20261129;
    cfg.controller.robust.feedback_time = feedback_time;
    return totalVariation(test::simulate(cfg).series, 30.0, 44.0);
  };
  const double rac = tv("rac", RobustConfig{}.feedback_time);
  const double low_passed = tv("pa_robust", RobustConfig{}.feedback_time);
  const double always = tv("pa_robust", 0.0);
  EXPECT_LE(low_passed, 2.0 * rac) << "rac " << rac;
  EXPECT_GT(always, 2.0 * rac) << "rac " << rac;
}

// pa_robust's error feedback -k e^T P B: it is pa_robust's alone (every other mode bit for bit
// the same whatever the key says), and on the limited, lagged elevator it takes the error of
// the switches back faster than the estimate alone (scenario 1 to 24 s, servo lag 0.05 s).
TEST(Saturation, ErrorFeedbackIsPaRobustsAndShrinksTheSwitchPeaks) {
  auto run = [](const std::string& mode, double k) {
    RunConfig cfg = limited(mode, Hedging::kPch);
    cfg.plant.dynamics.time_constant = 0.05;
    cfg.scenario.theta.resize(3);
    cfg.scenario.theta[2].until = 24.0;
    cfg.scenario.reference = {{24.0, 0.1}};
    cfg.controller.robust.error_feedback = k;
    return test::simulate(cfg);
  };
  EXPECT_GT(RobustConfig{}.error_feedback, 0.0);
  for (const std::string& mode : modeNameList()) {
    if (mode == "pa_robust") continue;
    const SimResult a = run(mode, 0.0), b = run(mode, 8.0);
    EXPECT_TRUE(sameBits(a.series.u, b.series.u)) << mode;
  }
  auto peak = [](const SimResult& r) {
    double p = 0.0;
    for (size_t k = 0; k < r.series.t.size(); ++k)
      if (r.series.t[k] >= 5.0) p = std::max(p, std::abs(r.series.e[k]));
    return p;
  };
  const double off = peak(run("pa_robust", 0.0)), on = peak(run("pa_robust", 8.0));
  EXPECT_LT(on, 0.8 * off) << "peak |e| after 5 s: k 0 " << off << ", k 8 " << on;
}
