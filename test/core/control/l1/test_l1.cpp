// The L1 adaptive law (docs/research/l1.md): its parameter table, each part (filter, predictor,
// adaptation, projection) against a hand calculation, and the closed loop on scenario 1.
#include <gtest/gtest.h>

#include <cmath>

#include "preadaptive_mrac/core/control/l1/l1_law.hpp"
#include "preadaptive_mrac/core/controller/mode_registry.hpp"
#include "preadaptive_mrac/core/schema/params.hpp"
#include "test_helpers.hpp"

using namespace preadaptive_mrac;

namespace {

struct Parts {
  RunConfig cfg = test::packageConfig("1");
  ControllerDesign design = designController(cfg.plant.A, cfg.plant.B, cfg.controller.Q, 1.0);
  Vec B = cfg.plant.B;
  Vec b_ref = cfg.plant.B1r;
  double dt = cfg.controller.sample_time;

  L1Law law(const L1Config& c, const Vec& theta0 = Vec::Zero(3)) const {
    return L1Law(design, B, b_ref, 0.0, c, dt, theta0, cfg.plant.x0);
  }
  /// The predictor's ODE as a Plant: x' = A_r x + B (theta^T x + u) + b_ref r.
  PlantConfig predictorPlant() const {
    PlantConfig p = cfg.plant;
    p.A = design.Ar;
    p.B1r = b_ref;
    return p;
  }
};

std::vector<std::string> problemsOf(const std::string& yaml_like_key, ParamValue v,
                                    double dt = 0.001) {
  ParamValue root = ParamValue::makeMap();
  root.setPath("controller.l1." + yaml_like_key, std::move(v));
  ParamReader r(root);
  const L1Config c = L1Config::read(r, "controller.l1");
  c.validate(r, "controller.l1", dt);
  return r.problems();
}

}  // namespace

TEST(L1Config, AbsentSectionGivesTheDocumentedDefaultsAndSaysSo) {
  ParamValue root = ParamValue::makeMap();
  ParamReader r(root);
  const L1Config c = L1Config::read(r, "controller.l1");
  c.validate(r, "controller.l1", 0.001);
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(c.gamma, L1Config().gamma);
  EXPECT_EQ(c.bandwidth, L1Config().bandwidth);
  ASSERT_EQ(r.defaultsUsed().size(), 1u);
  EXPECT_NE(r.defaultsUsed()[0].find("controller.l1"), std::string::npos);
}

TEST(L1Config, EveryBadValueIsNamedAtOnce) {
  ParamValue root = ParamValue::makeMap();
  root.setPath("controller.l1.gamma", ParamValue::makeDouble(-1.0));
  root.setPath("controller.l1.bandwidth", ParamValue::makeDouble(0.0));
  root.setPath("controller.l1.theta_max", ParamValue::makeDouble(std::nan("")));
  root.setPath("controller.l1.epsilon", ParamValue::makeDouble(2.0));
  ParamReader r(root);
  const L1Config c = L1Config::read(r, "controller.l1");
  c.validate(r, "controller.l1", 0.001);
  ASSERT_EQ(r.problems().size(), 4u);
  const std::string all = r.problems()[0] + r.problems()[1] + r.problems()[2] + r.problems()[3];
  for (const char* k : {"controller.l1.gamma: must be in (0, ", "controller.l1.bandwidth: must",
                        "controller.l1.theta_max: expected a finite number",
                        "controller.l1.epsilon: must be in (0, 1]"})
    EXPECT_NE(all.find(k), std::string::npos) << k << " in " << all;
}

TEST(L1Config, WrongTypeIsOneProblemAndBandwidthAboveNyquistIsRefused) {
  const auto wrong = problemsOf("gamma", ParamValue::makeString("fast"));
  ASSERT_EQ(wrong.size(), 1u);
  EXPECT_NE(wrong[0].find("controller.l1.gamma"), std::string::npos);
  // pi / 1 ms = 3141.6 rad/s.
  EXPECT_TRUE(problemsOf("bandwidth", ParamValue::makeDouble(3000.0)).empty());
  const auto fast = problemsOf("bandwidth", ParamValue::makeDouble(4000.0));
  ASSERT_EQ(fast.size(), 1u);
  EXPECT_NE(fast[0].find("controller.l1.bandwidth: must be below pi / sample_time"),
            std::string::npos);
  EXPECT_EQ(problemsOf("typo", ParamValue::makeDouble(1.0)).size(), 0u);  // caller rejects unused
}

TEST(L1Filter, StepResponseIsTheContinuousFilterSampled) {
  // C(s) = w / (s + w) fed a unit step: y(t) = 1 - exp(-w t), and the discretisation is exact
  // for an input held over each sample, so y_k = 1 - exp(-w k dt) to rounding.
  const double w = 50.0, dt = 0.001;
  LowPassFilter f(w, dt);
  double y = 0.0;
  for (int k = 1; k <= 200; ++k) {
    y = f.update(1.0);
    ASSERT_NEAR(y, 1.0 - std::exp(-w * k * dt), 1e-13) << "k = " << k;
  }
  // Unit DC gain; half the input after ln 2 / w.
  for (int k = 0; k < 2000; ++k) y = f.update(1.0);
  EXPECT_NEAR(y, 1.0, 1e-12);
  LowPassFilter g(w, dt);
  int k_half = 0;
  while (g.update(1.0) < 0.5) ++k_half;
  EXPECT_NEAR((k_half + 1) * dt, std::log(2.0) / w, dt);
}

TEST(L1Predictor, FollowsTheReferenceDynamicsWithItsInputHeld) {
  // With adaptation frozen the predictor is xh' = A_r xh + B (u_ad + theta_hat^T x) + b_ref r,
  // RK4 with the input held: the same numbers as a Plant with A := A_r integrating that ODE.
  Parts p;
  L1Config c;
  Vec theta0(3);
  theta0 << 0.3, -0.2, 0.5;
  L1Law law = p.law(c, theta0);
  Plant ref(p.predictorPlant());
  const Vec zero = Vec::Zero(3);
  Vec x(3);
  for (int k = 0; k < 3000; ++k) {
    x << 0.05 * std::sin(0.002 * k), 0.1 + 0.02 * std::cos(0.003 * k), 0.01;
    const double r = k < 1500 ? 0.1 : 0.05;
    const double u = law.command(x, r);
    ASSERT_NEAR((law.xHat() - ref.state()).cwiseAbs().maxCoeff(), 0.0, 1e-12) << "k = " << k;
    law.advance(x, r, u, /*adapt=*/false);
    // theta^T x + u as one held input of the plant with theta = 0.
    ref.step(p.dt, zero, u + theta0.dot(x), r);
  }
  EXPECT_EQ((law.thetaHat() - theta0).norm(), 0.0);
  EXPECT_GT(law.xHat().norm(), 1e-3);  // it moved
}

TEST(L1Adaptation, StepMovesAlongMinusGammaXTimesPredictionErrorPB) {
  // One Euler step from theta_hat = 0 with a known prediction error: exactly
  // -dt Gamma x (xt^T P B), well inside Omega (no projection).
  Parts p;
  L1Config c;
  c.gamma = 200.0;
  L1Law law = p.law(c);
  Vec x(3);
  x << 0.2, 0.1, -0.05;
  law.advance(x, 0.1, 0.0);  // xh = x0 = 0: xt = -x
  const Vec xt = law.predictionError();
  EXPECT_NEAR((xt + x).norm(), 0.0, 1e-15);
  const Vec expected = -p.dt * c.gamma * xt.dot(p.design.P * p.B) * x;
  EXPECT_NEAR((law.thetaHat() - expected).norm(), 0.0, 1e-15);
}

TEST(L1Adaptation, EstimatesTheMatchedUncertaintyOfThePredictorPlant) {
  // Open loop: the 'plant' is the predictor's ODE with a true theta (the structure matches, and
  // A_r + B theta^T is still Hurwitz) driven by a rich input the law does not choose; the
  // estimate converges to theta and the prediction error vanishes.
  Parts p;
  L1Config c;
  c.gamma = 5000.0;
  L1Law law = p.law(c);
  Plant plant(p.predictorPlant());
  Vec theta(3);
  theta << 0.2, -0.1, 0.3;
  double early_xt = 0.0, late_xt = 0.0;
  const int steps = 60000;
  for (int k = 0; k < steps; ++k) {
    const Vec x = plant.state();
    const double t = k * p.dt;
    const double r = 0.1 * std::sin(0.7 * t) + 0.05 * std::sin(3.1 * t);
    const double u = 0.2 * std::sin(1.3 * t) + 0.1 * std::sin(4.7 * t);
    law.advance(x, r, u);
    if (k > 100 && k < 2000) early_xt = std::max(early_xt, law.predictionError().norm());
    if (k > steps - 5000) late_xt = std::max(late_xt, law.predictionError().norm());
    plant.step(p.dt, theta, u, r);
  }
  std::printf("|theta_hat - theta| %.3g, |xt| early %.3g late %.3g\n",
              (law.thetaHat() - theta).norm(), early_xt, late_xt);
  EXPECT_LT((law.thetaHat() - theta).norm(), 0.02);
  EXPECT_LT(late_xt, 0.05 * early_xt);
}

TEST(L1Adaptation, ProjectionKeepsTheEstimateInOmega) {
  Parts p;
  L1Config c;
  c.gamma = 1e6;
  c.theta_max = 2.0;
  Vec big(3);
  big << 5.0, 5.0, 5.0;
  L1Law law = p.law(c, big);  // the initial estimate is projected too
  EXPECT_NEAR(law.thetaHat().norm(), 2.0, 1e-12);
  Vec x(3);
  x << 0.3, 0.2, -0.1;
  for (int k = 0; k < 2000; ++k) {
    law.command(x, 0.1);
    law.advance(x, 0.1, 0.0);
    ASSERT_LE(law.thetaHat().norm(), 2.0 + 1e-12) << "k = " << k;
  }
  // On the boundary the outward part of an update is removed, the tangential part kept.
  Vec th(3), y(3);
  th << 2.0, 0.0, 0.0;
  y << 1.0, 1.0, 0.0;
  projectUpdate(th, 2.0, 0.1, &y);
  EXPECT_NEAR(y[0], 0.0, 1e-15);
  EXPECT_EQ(y[1], 1.0);
  // Inward updates pass unchanged.
  y << -1.0, 1.0, 0.0;
  projectUpdate(th, 2.0, 0.1, &y);
  EXPECT_EQ(y[0], -1.0);
}

TEST(L1Law, WideFilterGivesTheUnfilteredAdaptiveTerm) {
  // C(s) -> 1 as omega grows: u_ad -> -theta_hat^T x (the MRAC form of the adaptive term).
  Parts p;
  L1Config c;
  c.bandwidth = 3000.0;  // exp(-3) per sample: five samples to within 1e-6
  Vec th(3);
  th << 1.0, 2.0, 3.0;
  L1Law law = p.law(c, th);
  Vec x(3);
  x << 0.1, 0.1, 0.1;
  double u = 0.0;
  for (int k = 0; k < 10; ++k) {
    u = law.command(x, 0.1);
    law.advance(x, 0.1, u, false);
  }
  EXPECT_NEAR(u, -th.dot(x), 1e-6);
}

TEST(L1Design, NormOfGMatchesAnIndependentComputationAndShrinksWithTheBandwidth) {
  // Reference values: the impulse response of G through scipy.linalg.expm at 0.1 ms steps,
  // trapezoids over 60 s
  // (docs/research/l1.md, "Choosing omega"), row 2 (q) the largest.
  Parts p;
  const std::pair<double, double> ref[] = {{20.0, 0.121754}, {50.0, 0.0535525}, {200.0, 0.0143325}};
  for (const auto& [w, g] : ref) EXPECT_NEAR(l1NormOfG(p.design.Ar, p.B, w), g, 5e-4 * g);
  double prev = 1e9;
  std::printf("omega [rad/s]  ||G||_L1   L1 condition with theta_max 25 (L = %.1f)\n",
              std::sqrt(3.0) * 25.0);
  for (double w : {10.0, 20.0, 50.0, 100.0, 150.0, 200.0, 500.0, 1000.0}) {
    const double g = l1NormOfG(p.design.Ar, p.B, w);
    std::printf("%13g  %9.4g  %.3g\n", w, g, g * std::sqrt(3.0) * 25.0);
    EXPECT_LT(g, prev);
    prev = g;
  }
}

namespace {
/// The closed loop of scenario 1 with the L1 law: u = -K x + u_ad; the output error against the
/// reference model x_r' = A_r x_r + B1r r (integrated as the controller integrates it).
struct L1Run {
  std::vector<double> peak;  // per theta window
  std::vector<double> tail;  // largest |e| over each window's last 2 s
  double peak_all = 0.0;
  double max_theta_hat = 0.0;
  bool finite = true;
};

L1Run runScenario1(const L1Config& c) {
  Parts p;
  L1Law law = p.law(c);
  ScenarioPlant sp(p.cfg.plant, p.cfg.scenario, p.dt);
  Plant ref(p.predictorPlant());  // with theta = 0 and u = 0: the reference model
  const Vec zero = Vec::Zero(3);
  const Vec K = p.design.K.transpose();
  const std::vector<double> sw = p.cfg.scenario.switchTimes();
  L1Run out;
  out.peak.assign(sw.size() + 1, 0.0);
  out.tail.assign(sw.size() + 1, 0.0);
  std::vector<double> ends = sw;
  ends.push_back(p.cfg.scenario.endTime());
  while (!sp.done()) {
    const Vec x = sp.measured();
    const double t = sp.time(), r = sp.reference();
    const double e = x[1] - ref.state()[1];
    size_t w = 0;
    while (w < sw.size() && t > sw[w]) ++w;
    out.peak[w] = std::max(out.peak[w], std::abs(e));
    if (t > ends[w] - 2.0) out.tail[w] = std::max(out.tail[w], std::abs(e));
    out.peak_all = std::max(out.peak_all, std::abs(e));
    const double u_bl = -K.dot(x);
    const double u_ad = law.command(x, r);
    sp.advance(u_bl + u_ad);
    law.advance(x, r, sp.lastApplied() - u_bl);
    ref.step(p.dt, zero, 0.0, r);
    out.max_theta_hat = std::max(out.max_theta_hat, law.thetaHat().norm());
    if (!x.allFinite()) {
      out.finite = false;
      break;
    }
  }
  return out;
}
}  // namespace

TEST(L1ClosedLoop, Scenario1ErrorIsSmallBoundedAndDecaysAfterEachJump) {
  // theta jumps 0.1 -> 1 -> 2 -> 4 (x ones) at 5, 20 and 45 s; regular adaptive control (gamma
  // 10) peaks at 0.014-0.019 rad after them (preadapt_sim --scenario 1 --mode rac). The L1 law
  // at its defaults keeps |e| below 5 mrad, and it decays to the reference model's output.
  L1Config c;
  const L1Run run = runScenario1(c);
  ASSERT_TRUE(run.finite);
  for (size_t w = 0; w < run.peak.size(); ++w)
    std::printf("window %zu: peak |e| %.3g rad, last 2 s %.3g rad\n", w, run.peak[w], run.tail[w]);
  EXPECT_LT(run.peak_all, 5e-3);
  EXPECT_LE(run.max_theta_hat, c.theta_max + 1e-12);
  for (size_t w = 1; w < run.peak.size(); ++w) {
    EXPECT_GT(run.peak[w], 0.0);
    EXPECT_LT(run.tail[w], 0.1 * run.peak[w]) << "window " << w;
  }
}

TEST(L1ClosedLoop, FasterAdaptationGivesSmallerPeaks) {
  // The L1 promise: the error bound shrinks as Gamma grows (filter fixed).
  L1Config slow, fast;
  slow.gamma = 100.0;
  fast.gamma = 10000.0;
  const L1Run a = runScenario1(slow), b = runScenario1(fast);
  ASSERT_TRUE(a.finite && b.finite);
  std::printf("peak |e|: Gamma 100 %.3g rad, Gamma 1e4 %.3g rad\n", a.peak_all, b.peak_all);
  EXPECT_LT(b.peak_all, 0.5 * a.peak_all);
}

TEST(L1Mode, ControllerInModeL1RunsTheLawAndMatchesItAlone) {
  // Mode l1 of the Controller (what preadapt_sim, the sweeps, families and nodes run): the same
  // closed loop as the law alone around the baseline, up to the reference model's
  // discretisation (the controller's RK4 polynomials against a Plant's RK4: rounding).
  RunConfig cfg = test::packageConfig("1");
  cfg.controller.mode = "l1";
  const SimResult res = test::simulate(cfg);
  const L1Run alone = runScenario1(L1Config());
  const auto& w = res.metrics.windows;
  ASSERT_EQ(w.size(), alone.peak.size());
  for (size_t i = 0; i < w.size(); ++i)
    EXPECT_NEAR(w[i].peak_abs_e, alone.peak[i], 1e-9 + 1e-6 * alone.peak[i]) << "window " << i;
  // theta_hat reported is the L1 estimate: it moves, stays in Omega, and is never reset.
  double th_max = 0.0, jump = 0.0;
  for (size_t k = 0; k < res.series.theta_hat.size(); ++k) {
    th_max = std::max(th_max, res.series.theta_hat[k].norm());
    if (k > 0)
      jump = std::max(jump, (res.series.theta_hat[k] - res.series.theta_hat[k - 1]).norm());
  }
  EXPECT_GT(th_max, 1.0);
  EXPECT_LE(th_max, cfg.controller.l1.theta_max + 1e-12);
  EXPECT_LT(jump, 0.1);
  // The adaptive term is filtered: u_ad is not -theta_hat^T x at a switch.
  double diff = 0.0;
  for (size_t k = 0; k < res.series.t.size(); ++k)
    diff =
        std::max(diff, std::abs(res.series.u_ad[k] + res.series.theta_hat[k].dot(res.series.x[k])));
  EXPECT_GT(diff, 1e-4);
}

TEST(L1Mode, ConfigNamesEveryBadL1KeyAndKnowsTheMode) {
  ParamValue tree = test::packageTree("1");
  tree.setPath("controller.mode", ParamValue::makeString("l1"));
  tree.setPath("controller.l1.gamma", ParamValue::makeDouble(-1.0));
  tree.setPath("controller.l1.bandwidth", ParamValue::makeDouble(5000.0));
  tree.setPath("controller.l1.gama", ParamValue::makeDouble(1.0));
  try {
    readRunConfig(tree);
    FAIL() << "accepted";
  } catch (const ConfigError& e) {
    const std::string all = e.what();
    EXPECT_NE(all.find("controller.l1.gamma: must be in (0"), std::string::npos) << all;
    EXPECT_NE(all.find("controller.l1.bandwidth: must be below pi / sample_time"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find("controller.l1.gama"), std::string::npos) << all;
  }
  tree = test::packageTree("1");
  tree.setPath("controller.mode", ParamValue::makeString("l1"));
  EXPECT_EQ(readRunConfig(tree).controller.mode, "l1");
  ASSERT_NE(findMode("l1"), nullptr);
  EXPECT_NE(modeNames(", ").find("oracle, l1"), std::string::npos);
}
