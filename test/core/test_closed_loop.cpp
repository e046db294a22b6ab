// Closed loop: determinism, regular adaptive control's behaviour, metrics bookkeeping.
#include <gtest/gtest.h>

#include <cmath>

#include "preadaptive_mrac/core/closed_loop.hpp"
#include "test_helpers.hpp"

using namespace preadaptive_mrac;

namespace {
std::string runJson(RunConfig cfg, const std::string& mode, std::uint64_t seed,
                    SimResult* out = nullptr) {
  cfg.controller.mode = mode;
  cfg.controller.seed = seed;
  Controller ctl(designModelOf(cfg.plant, cfg.controller), cfg.controller);
  ClosedLoop loop(cfg.plant, cfg.scenario, &ctl);
  SimOptions opt;
  opt.dt = cfg.controller.sample_time;
  opt.record_series = out != nullptr;
  SimResult res = loop.run(opt);
  RunInfo info;
  info.scenario = "1";
  info.mode = mode;
  info.seed = seed;
  info.dt = opt.dt;
  info.wall_time_s = 0.0;  // the only field that may differ between identical runs
  const std::string j = runSummaryJson(info, ctl, res);
  if (out) *out = std::move(res);
  return j;
}
}  // namespace

TEST(ClosedLoop, SameSeedGivesIdenticalJson) {
  RunConfig cfg = test::packageConfig("1");
  cfg.controller.c_ed = 0.015;  // detect every switch, so learning really runs
  for (const char* m : {"pa", "pa_learn", "pa_learn_exact"}) {
    const std::string a = runJson(cfg, m, 5), b = runJson(cfg, m, 5);
    EXPECT_EQ(a, b) << m;
    EXPECT_NE(a.find("\"events\":[{"), std::string::npos);
  }
}

TEST(ClosedLoop, DifferentSeedsGiveDifferentInitialWeights) {
  const RunConfig cfg = test::packageConfig("1");
  PreadaptNetwork a(3, 3, 1, 1.0), b(3, 3, 2, 1.0), a2(3, 3, 1, 1.0);
  EXPECT_GT((a.state().W - b.state().W).norm(), 1e-3);
  EXPECT_GT((a.state().V - b.state().V).norm(), 1e-3);
  EXPECT_EQ((a.state().W - a2.state().W).norm(), 0.0);
  // Weights lie in [-scale, scale].
  EXPECT_LE(a.state().W.cwiseAbs().maxCoeff(), 1.0);
  // And the runs differ when preadaptation acts on them.
  RunConfig c = cfg;
  c.controller.c_ed = 0.015;
  EXPECT_NE(runJson(c, "pa", 1), runJson(c, "pa", 2));
}

TEST(ClosedLoop, RegularAdaptiveControlStaysBoundedAndRecoversAfterEachSwitch) {
  SimResult res;
  runJson(test::packageConfig("1"), "rac", 1, &res);
  const Series& s = res.series;
  ASSERT_EQ(s.t.size(), 60000u);
  for (size_t k = 0; k < s.t.size(); ++k) {
    ASSERT_TRUE(s.x[k].allFinite());
    ASSERT_LT(s.x[k].cwiseAbs().maxCoeff(), 1.0) << "t = " << s.t[k];
    ASSERT_LT(s.theta_hat[k].cwiseAbs().maxCoeff(), 20.0) << "t = " << s.t[k];
  }
  // After every switch the error grows, then decays: over the last 2 s of each window the
  // largest |e| is below a fifth of the window's peak, and alpha tracks r = 0.1 rad.
  const auto& w = res.metrics.windows;
  ASSERT_EQ(w.size(), 4u);
  for (size_t i = 1; i < w.size(); ++i) {
    double tail = 0.0;
    for (size_t k = 0; k < s.t.size(); ++k)
      if (s.t[k] > w[i].t_end - 2.0 && s.t[k] <= w[i].t_end)
        tail = std::max(tail, std::abs(s.e[k]));
    EXPECT_GT(w[i].peak_abs_e, 0.005) << "window " << i;
    EXPECT_LT(tail, 0.2 * w[i].peak_abs_e) << "window " << i;
  }
  EXPECT_NEAR(s.x.back()[1], 0.1, 2e-3);
  // theta_hat never reset in rac: it only moves by adaptation (no jumps larger than one step's).
  for (const Event& e : res.events) EXPECT_FALSE(e.reset);
}

TEST(ClosedLoop, MetricsMatchTheSeries) {
  SimResult res;
  runJson(test::packageConfig("1"), "rac", 1, &res);
  const auto& w = res.metrics.windows;
  double peak = 0.0, iae = 0.0, umax = 0.0;
  double wpeak[4] = {0, 0, 0, 0};
  for (size_t k = 0; k < res.series.t.size(); ++k) {
    const double t = res.series.t[k], a = std::abs(res.series.e[k]);
    peak = std::max(peak, a);
    iae += a * 0.001;
    umax = std::max(umax, std::abs(res.series.u[k]));
    const int wi = t <= 5 ? 0 : t <= 20 ? 1 : t <= 45 ? 2 : 3;
    wpeak[wi] = std::max(wpeak[wi], a);
  }
  EXPECT_DOUBLE_EQ(res.metrics.peak_abs_e, peak);
  EXPECT_NEAR(res.metrics.iae, iae, 1e-12);
  EXPECT_DOUBLE_EQ(res.metrics.max_abs_u, umax);
  for (int i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(w[static_cast<size_t>(i)].peak_abs_e, wpeak[i]);
  EXPECT_DOUBLE_EQ(w[0].t_start, 0.0);
  EXPECT_DOUBLE_EQ(w[1].t_start, 5.0);
  EXPECT_DOUBLE_EQ(w[2].t_start, 20.0);
  EXPECT_DOUBLE_EQ(w[3].t_start, 45.0);
  EXPECT_DOUBLE_EQ(w[3].t_end, 60.0);
  // Each RECOVERED event's cost is the integral of |e| since its onset.
  for (size_t i = 0; i + 1 < res.events.size(); ++i) {
    if (res.events[i].type != Event::Type::kOnset) continue;
    const Event& rec = res.events[i + 1];
    ASSERT_EQ(rec.type, Event::Type::kRecovered);
    double E = 0.0;
    for (size_t k = 0; k < res.series.t.size(); ++k)
      if (res.series.t[k] >= res.events[i].t - 1e-9 && res.series.t[k] < rec.t - 1e-9)
        E += std::abs(res.series.e[k]) * 0.001;
    EXPECT_NEAR(rec.cost, E, 1e-12);
  }
}

TEST(ClosedLoop, ThetaSwitchesRightAfterTheListedTime) {
  const RunConfig cfg = test::packageConfig("1");
  ScenarioPlant sim(cfg.plant, cfg.scenario, 0.001);
  EXPECT_EQ(sim.totalSteps(), 60000);
  EXPECT_DOUBLE_EQ(sim.theta()[0], 0.1);
  while (sim.step() < 4999) sim.advance(0.0);
  EXPECT_DOUBLE_EQ(sim.theta()[0], 0.1);  // step [4.999, 5.0]
  sim.advance(0.0);
  EXPECT_DOUBLE_EQ(sim.theta()[0], 1.0);  // step [5.0, 5.001]
}

TEST(ClosedLoop, ExactModeNeedsTruth) {
  RunConfig cfg = test::packageConfig("1");
  cfg.controller.mode = "pa_learn_exact";
  Controller ctl(designModelOf(cfg.plant, cfg.controller), cfg.controller);
  EXPECT_TRUE(ctl.needsTruth());
  Vec x = Vec::Zero(3);
  StepInput in;
  in.x = &x;
  EXPECT_THROW(ctl.step(in), std::invalid_argument);
}

TEST(ClosedLoop, PreadaptationResetsToTheNetworkOutput) {
  RunConfig cfg = test::packageConfig("1");
  cfg.controller.c_ed = 0.015;
  SimResult res;
  runJson(cfg, "pa", 3, &res);
  PreadaptNetwork net(cfg.controller.hidden, 3, 3, cfg.controller.init_scale);
  int onsets = 0;
  for (const Event& e : res.events) {
    if (e.type != Event::Type::kOnset) continue;
    ++onsets;
    ASSERT_TRUE(e.reset);
    Vec th;
    net.forward(NetInput(e.e, std::abs(e.e_dot)), &th);
    EXPECT_LT((th - e.theta_hat_after).norm(), 1e-15);
  }
  EXPECT_GE(onsets, 3);
}

// The elevator effort is of the applied elevator: its peak, the time at the travel and at the
// rate limit, and the total variation over the steady last half of each window.
TEST(ClosedLoop, EffortCountsTheAppliedElevator) {
  MetricsAccumulator acc({1.0}, 2.0, {});
  ActuatorLimits lim;
  lim.enabled = true;
  lim.max_deflection = 0.3;
  lim.max_rate = 1.0;  // 0.1 rad per step of 0.1 s
  acc.setLimits(lim);
  // Window 0 (0, 1]: up at the rate limit to the travel, held; window 1: a buzz of 0.01.
  // Samples 0..10 (t <= 1.0) are window 0, 11..19 window 1.
  const double u[] = {0.1, 0.2,  0.3, 0.3,  0.3, 0.3,  0.3, 0.3,  0.3, 0.3,
                      0.3, 0.29, 0.3, 0.29, 0.3, 0.29, 0.3, 0.29, 0.3, 0.29};
  for (int k = 0; k < 20; ++k) acc.addApplied(0.1 * k, 0.1, u[k]);
  const auto& m = acc.metrics();
  EXPECT_DOUBLE_EQ(m.effort.peak_abs_u, 0.3);
  EXPECT_NEAR(m.effort.time_at_rate, 0.3, 1e-12);    // 0 -> 0.1 -> 0.2 -> 0.3
  EXPECT_NEAR(m.effort.time_at_travel, 1.3, 1e-12);  // 9 samples + 4 in window 1
  // Window 1's steady half is t >= 1.5: samples 15..19, four steps of 0.01 between them.
  EXPECT_NEAR(m.windows[1].steady_tv, 0.04, 1e-12);
  EXPECT_NEAR(m.windows[0].steady_tv, 0.0, 1e-12);
  EXPECT_NEAR(m.effort.steady_tv, 0.04, 1e-12);
  EXPECT_NEAR(m.windows[0].time_at_limit, 1.1, 1e-12);
}

// Without limits the applied elevator is the command: its peak is max|u| and no time is at a
// limit; with the aircraft's elevator, no applied deflection exceeds the travel.
TEST(ClosedLoop, EffortOfThePaperRunAndOfTheLimitedElevator) {
  SimResult res;
  RunConfig cfg = test::packageConfig("3");
  runJson(cfg, "rac", 1, &res);
  EXPECT_DOUBLE_EQ(res.metrics.effort.peak_abs_u, res.metrics.max_abs_u);
  EXPECT_EQ(res.metrics.effort.time_at_travel, 0.0);
  EXPECT_EQ(res.metrics.effort.time_at_rate, 0.0);
  EXPECT_GT(res.metrics.effort.steady_tv, 0.0);
  cfg.plant.actuator.enabled = true;
  cfg.plant.actuator.max_deflection = 0.35;
  cfg.plant.actuator.max_rate = 0.65;
  runJson(cfg, "rac", 1, &res);
  EXPECT_LE(res.metrics.effort.peak_abs_u, 0.35 + 1e-12);
  EXPECT_GT(res.metrics.effort.time_at_travel + res.metrics.effort.time_at_rate, 0.0);
  double at_limit = 0.0;
  for (const auto& w : res.metrics.windows) at_limit += w.time_at_limit;
  EXPECT_LE(at_limit, res.metrics.effort.time_at_travel + res.metrics.effort.time_at_rate + 1e-9);
  EXPECT_GT(at_limit, 0.0);
}
