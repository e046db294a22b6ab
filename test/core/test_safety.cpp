// Safety options of the core: actuator limits, projection onto Omega, measurement noise,
// attention debounce and hysteresis. Each test fails without its feature.
#include <gtest/gtest.h>

#include <cmath>

#include "preadaptive_mrac/core/closed_loop.hpp"
#include "test_helpers.hpp"

using namespace preadaptive_mrac;

TEST(ActuatorLimits, RateThenMagnitude) {
  ActuatorLimits l;
  EXPECT_EQ(l.apply(5.0, 0.0, 0.001), 5.0);  // disabled: identity
  l.enabled = true;
  l.max_deflection = 0.4;
  l.max_rate = 1.0;
  EXPECT_DOUBLE_EQ(l.apply(0.3, 0.0, 0.001), 0.001);  // rate: 1 rad/s x 1 ms
  EXPECT_DOUBLE_EQ(l.apply(-0.3, 0.0, 0.001), -0.001);
  EXPECT_DOUBLE_EQ(l.apply(0.3995, 0.3999, 0.001), 0.3995);
  EXPECT_DOUBLE_EQ(l.apply(0.9, 0.3999, 0.001), 0.4);  // magnitude
}

TEST(ActuatorLimits, PlantAndControllerRespectThemAndAdaptationFreezes) {
  RunConfig cfg = test::packageConfig("3");
  cfg.plant.actuator = {true, 0.3, 1.0};
  cfg.controller.mode = "pa_learn";
  cfg.controller.c_ed = 0.015;
  cfg.controller.hedging = Hedging::kNone;  // freezing is the unhedged law's answer to the limit
  const SimResult res = test::simulate(cfg);
  const Series& s = res.series;
  int saturated = 0;
  for (size_t k = 0; k < s.t.size(); ++k) {
    ASSERT_LE(std::abs(s.u[k]), 0.3 + 1e-15) << s.t[k];
    if (k > 0) {
      ASSERT_LE(std::abs(s.u[k] - s.u[k - 1]), 1.0 * 0.001 + 1e-15) << s.t[k];
    }
    if (s.saturated[k]) {
      ++saturated;
      // Frozen: the estimate used at the next sample is the same unless an onset reset it.
      if (k + 1 < s.t.size() && s.phase[k + 1] == s.phase[k]) {
        EXPECT_EQ((s.theta_hat[k + 1] - s.theta_hat[k]).norm(), 0.0) << s.t[k];
      }
    }
  }
  EXPECT_GT(saturated, 100);  // scenario 3 does push the elevator into the limits
  for (size_t k = 0; k < s.t.size(); ++k) ASSERT_TRUE(s.x[k].allFinite());
  // Without limits the same run exceeds them: the test exercises the limits.
  cfg.plant.actuator.enabled = false;
  EXPECT_GT(test::simulate(cfg).metrics.max_abs_u, 0.3);
}

TEST(Projection, EstimatesStayInOmegaUnderNoiseAndLargeJumps) {
  RunConfig cfg = test::packageConfig("3");
  cfg.controller.mode = "pa_learn";
  cfg.controller.c_ed = 0.015;
  cfg.controller.init_scale = 20.0;  // wild network outputs at every reset
  cfg.plant.noise.std = Eigen::Vector3d(0.0, 2e-4, 2e-4);
  cfg.plant.noise.seed = 4;
  const double theta_max = 4.0;  // smaller than scenario 3's true |theta| (up to 17.3)
  // Without projection the estimate leaves the ball: the check below can fail.
  double worst_free = 0.0;
  for (const auto& th : test::simulate(cfg).series.theta_hat)
    worst_free = std::max(worst_free, th.norm());
  ASSERT_GT(worst_free, theta_max);
  cfg.controller.projection = true;
  cfg.controller.theta_max = theta_max;
  cfg.controller.projection_epsilon = 0.1;
  const SimResult res = test::simulate(cfg);
  double worst = 0.0;
  for (const auto& th : res.series.theta_hat) worst = std::max(worst, th.norm());
  EXPECT_LE(worst, theta_max * (1 + 1e-12));
  for (const auto& e : res.events) {
    if (e.reset) {
      EXPECT_LE(e.theta_hat_after.norm(), theta_max * (1 + 1e-12));
    }
  }
  for (const auto& x : res.series.x) ASSERT_TRUE(x.allFinite());
}

TEST(Projection, InsideTheInnerBallItChangesNothing) {
  RunConfig cfg = test::packageConfig("1");
  cfg.controller.mode = "rac";
  const SimResult free = test::simulate(cfg);
  cfg.controller.projection = true;
  cfg.controller.theta_max = 25.0;  // scenario 1's estimate stays below 2
  const SimResult proj = test::simulate(cfg);
  ASSERT_EQ(free.series.theta_hat.size(), proj.series.theta_hat.size());
  for (size_t k = 0; k < free.series.t.size(); ++k)
    ASSERT_EQ((free.series.theta_hat[k] - proj.series.theta_hat[k]).norm(), 0.0);
}

TEST(Noise, SeededAndReproducible) {
  RunConfig cfg = test::packageConfig("1");
  cfg.controller.mode = "rac";
  const SimResult clean = test::simulate(cfg);
  cfg.plant.noise.std = Eigen::Vector3d(0.0, 1e-3, 1e-3);
  cfg.plant.noise.seed = 7;
  const SimResult a = test::simulate(cfg), b = test::simulate(cfg);
  EXPECT_EQ(a.series.e, b.series.e);
  EXPECT_NE(a.series.e, clean.series.e);
  cfg.plant.noise.seed = 8;
  EXPECT_NE(test::simulate(cfg).series.e, a.series.e);
  // Sample statistics of the source: mean 0, variance 1.
  GaussianSource g(1);
  double m = 0, v = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double x = g.next();
    m += x;
    v += x * x;
  }
  EXPECT_NEAR(m / n, 0.0, 0.01);
  EXPECT_NEAR(v / n, 1.0, 0.02);
}

TEST(Attention, DebounceAndHysteresisSuppressChatter) {
  // |e| wanders around c_e with fast flips: every flip is a crossing with a high rate.
  auto chatter = [](double t) { return 0.005 + 0.0004 * std::sin(2 * M_PI * 25 * t); };
  auto count = [&](int confirm, double hyst) {
    VelocityEstimator vel(0.01, 0.001);
    Attention att(0.005, 0.02, confirm, hyst);
    int events = 0;
    for (int k = 0; k < 2000; ++k) {
      const double e = chatter(k * 0.001);
      events += att.update(e, vel.update(e)) != Attention::Result::kNone;
    }
    return events;
  };
  const int paper = count(0, 0.0);
  EXPECT_GT(paper, 20);
  EXPECT_LT(count(25, 0.0), paper / 5);   // a crossing must hold 25 ms: the 20 ms half-waves fail
  EXPECT_LT(count(0, 0.001), paper / 2);  // no recoveries: |e| never falls below c_e - 1 mrad
  // A real, sustained fast rise is still an onset with debounce on, a few samples later.
  VelocityEstimator vel(0.01, 0.001);
  Attention att(0.005, 0.02, 5, 0.001);
  int onset_k = -1;
  for (int k = 0; k < 300 && onset_k < 0; ++k) {
    const double e = 0.05 * k * 0.001;
    if (att.update(e, vel.update(e)) == Attention::Result::kOnset) onset_k = k;
  }
  EXPECT_EQ(onset_k, 105);  // crossing at k = 100, confirmed 5 samples later
}

TEST(Config, SafetyOptionsAreValidated) {
  ParamValue t = test::packageTree();
  t.setPath("plant.actuator.max_rate", ParamValue::makeDouble(0.0));
  t.setPath("plant.noise.std",
            ParamValue::makeList({ParamValue::makeDouble(0), ParamValue::makeDouble(-1),
                                  ParamValue::makeDouble(0)}));
  t.setPath("controller.attention.hysteresis", ParamValue::makeDouble(0.01));
  t.setPath("controller.attention.confirm_samples", ParamValue::makeInt(-2));
  t.setPath("controller.projection.epsilon", ParamValue::makeDouble(0.0));
  std::string all;
  try {
    readRunConfig(t);
  } catch (const ConfigError& e) {
    all = e.what();
  }
  for (const char* key : {"plant.actuator.max_rate: must be > 0", "plant.noise.std: must be >= 0",
                          "controller.attention.hysteresis: must be in [0, c_e",
                          "controller.attention.confirm_samples: must be in [0, 100000]",
                          "controller.projection.epsilon: must be in (0, 1]"})
    EXPECT_NE(all.find(key), std::string::npos) << key << "\n" << all;
}

TEST(InputGuard, RejectsMalformedSamplesWithoutRefreshingTheTimer) {
  InputGuard g(3, 0.05);
  EXPECT_TRUE(g.stale(0.0));  // nothing valid yet
  const double ok[3] = {0.0, 0.1, 0.0};
  EXPECT_TRUE(g.accept(1.0, ok, 3));
  EXPECT_FALSE(g.stale(1.04));
  const double nan[3] = {0.0, std::nan(""), 0.0};
  const double inf[3] = {0.0, 0.0, INFINITY};
  std::string why;
  EXPECT_FALSE(g.accept(1.03, nan, 3, &why));
  EXPECT_EQ(why, "x[1] is nan");
  EXPECT_FALSE(g.accept(1.04, inf, 3, &why));
  EXPECT_EQ(why, "x[2] is inf");
  EXPECT_FALSE(g.accept(1.045, ok, 2, &why));
  EXPECT_EQ(why, "x has 2 entries, expected 3");
  EXPECT_EQ(g.rejected(), 3u);
  EXPECT_EQ(g.accepted(), 1u);
  // Rejected samples did not refresh the timer: stale 50 ms after the last valid one.
  EXPECT_TRUE(g.stale(1.051));
  EXPECT_NEAR(g.age(1.051), 0.051, 1e-12);
  // (the policy's names are parsed by the parser generated from params/nodes.yaml:
  // test_ros_node_params, ControllerNodeParams.StaleKeysReadAndKnown)
}

TEST(InputGuard, SafeCommandIsBaselineOrZeroWithinLimits) {
  RunConfig cfg = test::packageConfig("1");
  Controller ctl(designModelOf(cfg.plant, cfg.controller), cfg.controller);
  Vec x(3);
  x << 0.1, 0.2, -0.1;
  EXPECT_NEAR(ctl.safeCommand(x, StalePolicy::kBaselineHold), -ctl.design().K.dot(x), 1e-15);
  EXPECT_EQ(ctl.safeCommand(x, StalePolicy::kZero), 0.0);
  cfg.plant.actuator = {true, 0.4, 1.0};
  Controller lim(designModelOf(cfg.plant, cfg.controller), cfg.controller);
  x << 0.0, 2.0, 0.0;  // baseline would ask for 2.3 rad
  EXPECT_NEAR(lim.safeCommand(x, StalePolicy::kBaselineHold), 0.001, 1e-15);  // rate-limited
}
