// Gradients of the learner: the exact sensitivity against finite differences of the simulated
// phase cost, and the network's dE/dW, dE/dV against finite differences of the network.
#include <gtest/gtest.h>

#include <iostream>

#include "preadaptive_mrac/core/closed_loop.hpp"
#include "preadaptive_mrac/core/control/paper/sensitivity_tracker.hpp"
#include "test_helpers.hpp"

using namespace preadaptive_mrac;

namespace {

struct PhaseResult {
  double E;
  Vec grad;
};

// Theta = 0.1 until 2 s, then 2: run 4 s (attention off: c_e huge), start a phase at t_u = 4 s
// with theta_hat = theta_I, run it for `length` s and return E and the tracked dE/dtheta_I.
PhaseResult fixedPhase(const RunConfig& base, const std::string& mode, const Vec& theta_I,
                       double length) {
  RunConfig cfg = base;
  cfg.controller.mode = mode;
  cfg.controller.c_e = 1e3;  // no attention events: the phase is fixed by the test
  Scenario sc;
  sc.name = "fixed_phase";
  sc.theta = {{2.0, Eigen::VectorXd::Constant(3, 0.1)},
              {4.0 + length + 1.0, Eigen::VectorXd::Constant(3, 2.0)}};
  sc.reference = {{4.0 + length + 1.0, 0.1}};
  Controller ctl(designModelOf(cfg.plant, cfg.controller), cfg.controller);
  const double dt = cfg.controller.sample_time;
  ScenarioPlant sim(cfg.plant, sc, dt);
  const auto k_u = static_cast<std::int64_t>(std::llround(4.0 / dt));
  const auto k_d = k_u + static_cast<std::int64_t>(std::llround(length / dt));
  Vec x;
  while (sim.step() < k_d) {
    if (sim.step() == k_u) ctl.startPhase(theta_I);
    x = sim.state();
    StepInput in;
    in.t = sim.time();
    in.x = &x;
    in.r = sim.reference();
    in.theta_true = &sim.theta();
    const StepOutput o = ctl.step(in);
    EXPECT_FALSE(o.event.has_value());
    sim.advance(o.u);
  }
  return {ctl.phaseCost(), ctl.phaseGradient()};
}

}  // namespace

TEST(Gradients, ExactSensitivityMatchesFiniteDifferenceOfPhaseCost) {
  const RunConfig cfg = test::packageConfig("1");
  Vec theta_I(3);
  theta_I << 0.5, 0.8, 1.2;  // away from the true theta = 2: a real transient to learn from
  for (double length : {1.0, 3.0}) {
    const PhaseResult base = fixedPhase(cfg, "pa_learn_exact", theta_I, length);
    ASSERT_GT(base.E, 0.0);
    const double h = 1e-4;
    Vec fd(3);
    for (int i = 0; i < 3; ++i) {
      Vec plus = theta_I, minus = theta_I;
      plus[i] += h;
      minus[i] -= h;
      fd[i] = (fixedPhase(cfg, "pa_learn_exact", plus, length).E -
               fixedPhase(cfg, "pa_learn_exact", minus, length).E) /
              (2 * h);
    }
    // Within a few percent of the gradient's size, component by component.
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(base.grad[i], fd[i], 0.05 * fd.norm())
          << "component " << i << ", phase length " << length << " s; exact "
          << base.grad.transpose() << " vs finite difference " << fd.transpose();
    EXPECT_LT((base.grad - fd).norm(), 0.05 * fd.norm());
    // The approximate gradient (Pi_hat) is measurably further off: the test can tell them apart.
    const PhaseResult approx = fixedPhase(cfg, "pa_learn", theta_I, length);
    std::cout << "phase " << length << " s: exact " << base.grad.transpose() << " | approx "
              << approx.grad.transpose() << " | finite difference " << fd.transpose()
              << " | relative error exact " << (base.grad - fd).norm() / fd.norm() << ", approx "
              << (approx.grad - fd).norm() / fd.norm() << std::endl;
    EXPECT_GT((approx.grad - fd).norm(), 2.0 * (base.grad - fd).norm());
  }
}

TEST(Gradients, ApproximateGradientDiffersFromExactButIsTracked) {
  // Pi_hat drops B (theta - theta_hat)^T: the approximate gradient is a different number.
  const RunConfig cfg = test::packageConfig("1");
  Vec theta_I(3);
  theta_I << 0.5, 0.8, 1.2;
  const PhaseResult exact = fixedPhase(cfg, "pa_learn_exact", theta_I, 3.0);
  const PhaseResult approx = fixedPhase(cfg, "pa_learn", theta_I, 3.0);
  EXPECT_DOUBLE_EQ(exact.E, approx.E);  // same closed loop: the gradient mode does not act on it
  EXPECT_GT((exact.grad - approx.grad).norm(), 1e-6);
  EXPECT_GT(approx.grad.norm(), 0.0);
}

TEST(Gradients, SensitivityPiMatchesSpec) {
  // Pi's blocks as docs/spec.md writes them.
  Mat Ar(2, 2);
  Ar << -1, 0.5, -0.2, -2;
  Vec B(2), PB(2), ev(2), x(2), th(2);
  B << 0.3, -1;
  PB << 0.7, 0.1;
  ev << 0.01, -0.02;
  x << 0.5, 0.25;
  th << 0.4, -0.3;
  SensitivityTracker st(Ar, B, PB, 10.0, 1);
  const PiMat P = st.pi(ev, x, th);
  const Eigen::Matrix2d tl = Ar + B * th.transpose();
  const Eigen::Matrix2d tr = -B * x.transpose();
  const Eigen::Matrix2d bl =
      10.0 * ev.dot(PB) * Eigen::Matrix2d::Identity() + 10.0 * x * PB.transpose();
  EXPECT_LT((P.topLeftCorner(2, 2) - tl).norm(), 1e-15);
  EXPECT_LT((P.topRightCorner(2, 2) - tr).norm(), 1e-15);
  EXPECT_LT((P.bottomLeftCorner(2, 2) - bl).norm(), 1e-15);
  EXPECT_EQ(P.bottomRightCorner(2, 2).norm(), 0.0);
  // accumulate() advances S by dt Pi S (Euler) without forming Pi.
  st.start();
  const SensMat S0 = st.S();
  st.accumulate(0.001, ev, x, th);
  const SensMat expect = S0 + 0.001 * P * S0;
  EXPECT_LT((st.S() - expect).norm(), 1e-14);
}

TEST(Gradients, NetworkGradientsMatchFiniteDifferences) {
  PreadaptNetwork net(3, 3, 7, 1.5);
  NetInput z(0.006, 0.8);  // larger |e_dot| so the hidden layer is off its midpoint
  Vec g(3);
  g << 0.3, -1.1, 0.4;
  // L = g . theta_I(W, V) has dL/dtheta_I = g, so its gradient is the network's dE/dW, dE/dV.
  auto L = [&](const PreadaptNetwork& n) {
    Vec th;
    n.forward(z, &th);
    return g.dot(th);
  };
  NetW dW;
  NetV dV;
  net.gradients(z, g, &dW, &dV);
  const double h = 1e-6;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      PreadaptNetwork p = net, m = net;
      p.state().W(j, i) += h;
      m.state().W(j, i) -= h;
      EXPECT_NEAR(dW(j, i), (L(p) - L(m)) / (2 * h), 1e-8) << "W " << j << "," << i;
    }
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j) {
      PreadaptNetwork p = net, m = net;
      p.state().V(k, j) += h;
      m.state().V(k, j) -= h;
      EXPECT_NEAR(dV(k, j), (L(p) - L(m)) / (2 * h), 1e-8) << "V " << k << "," << j;
    }
  EXPECT_GT(dV.norm(), 1e-6);
}

TEST(Gradients, LearningStepDescends) {
  // One learn() with a small rate lowers L = g . theta_I, and counts the episode.
  PreadaptNetwork net(3, 3, 11, 1.0);
  NetInput z(0.005, 0.03);
  Vec g(3);
  g << 0.2, 0.1, -0.05;
  Vec before, after;
  net.forward(z, &before);
  net.learn(z, g, 0.1);
  net.forward(z, &after);
  EXPECT_LT(g.dot(after), g.dot(before));
  EXPECT_EQ(net.state().episodes, 1);
}
