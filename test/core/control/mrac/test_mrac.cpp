// The MRAC law (mrac/mrac_law.hpp, docs/spec.md "Adaptation") against a hand calculation: the
// command, one Euler step of the update, the freeze, the reset and the projection's ball.
#include <gtest/gtest.h>

#include "preadaptive_mrac/core/control/mrac/mrac_law.hpp"
#include "test_helpers.hpp"

using namespace preadaptive_mrac;

namespace {

struct Parts {
  ControllerConfig cfg = test::packageConfig("1").controller;
  Vec PB = (Vec(3) << 0.4, -0.7, 1.3).finished();
  Vec x = (Vec(3) << -0.25, 0.1, 0.035).finished();
  Vec ev = (Vec(3) << 0.002, -0.004, 0.01).finished();

  LawInput input(double r = 0.1) const {
    LawInput in;
    in.x = &x;
    in.ev = &ev;
    in.r = r;
    return in;
  }
};

}  // namespace

TEST(MracLaw, CommandIsMinusThetaHatTimesXPlusK0R) {
  Parts p;
  p.cfg.theta_hat0 = (Vec(3) << 0.5, -1.0, 2.0).finished();
  p.cfg.k0 = 0.3;
  const MracLaw law(p.cfg, p.PB);
  const double want = -(0.5 * -0.25 + -1.0 * 0.1 + 2.0 * 0.035) + 0.3 * 0.1;
  EXPECT_NEAR(law.command(p.input()), want, 1e-15);
}

TEST(MracLaw, OneStepIsGammaTimesXTimesEvTransposePBTimesDt) {
  Parts p;
  p.cfg.theta_hat0 = Vec::Zero(3);
  p.cfg.gamma = 10.0;
  p.cfg.projection = false;
  MracLaw law(p.cfg, p.PB);
  law.advance(p.input(), true);
  const double s = p.ev.dot(p.PB);  // e_v^T P B
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(law.estimate()(i), p.cfg.sample_time * 10.0 * s * p.x(i), 1e-15) << i;
  // The direction: a positive e_v^T P B moves theta_hat along x.
  ASSERT_GT(s, 0.0);
  EXPECT_GT(law.estimate().dot(p.x), 0.0);
}

TEST(MracLaw, FrozenStepAndResetKeepTheEstimate) {
  Parts p;
  p.cfg.theta_hat0 = (Vec(3) << 0.1, 0.2, 0.3).finished();
  MracLaw law(p.cfg, p.PB);
  law.advance(p.input(), false);
  EXPECT_EQ(law.estimate(), p.cfg.theta_hat0);
  law.advance(p.input(), true);
  EXPECT_NE(law.estimate(), p.cfg.theta_hat0);
  law.reset();
  EXPECT_EQ(law.estimate(), p.cfg.theta_hat0);
}

TEST(MracLaw, ProjectionKeepsTheEstimateInItsBall) {
  Parts p;
  p.cfg.theta_hat0 = Vec::Zero(3);
  p.cfg.gamma = 1e4;  // large steps: the Euler step would leave the ball without the clamp
  p.cfg.projection = true;
  p.cfg.theta_max = 2.0;
  MracLaw law(p.cfg, p.PB);
  double largest = 0.0;
  for (int k = 0; k < 2000; ++k) {
    law.advance(p.input(), true);
    largest = std::max(largest, law.estimate().norm());
  }
  EXPECT_LE(largest, 2.0 + 1e-12);
  EXPECT_GT(largest, 1.9);  // it did reach the boundary layer
  // Without the projection the same steps leave it.
  p.cfg.projection = false;
  MracLaw free_law(p.cfg, p.PB);
  for (int k = 0; k < 2000; ++k) free_law.advance(p.input(), true);
  EXPECT_GT(free_law.estimate().norm(), 2.0);
  // One Euler step from inside the inner ball (no projection there) across the whole boundary
  // layer: the clamp brings it back onto the ball.
  p.cfg.projection = true;
  p.cfg.gamma = 1e7;
  MracLaw jump(p.cfg, p.PB);
  jump.advance(p.input(), true);
  EXPECT_NEAR(jump.estimate().norm(), 2.0, 1e-12);
  // An estimate set from outside (a preadaptation reset) is brought back by constrain().
  *law.mutableEstimate() = (Vec(3) << 3.0, 4.0, 0.0).finished();
  law.constrain();
  EXPECT_NEAR(law.estimate().norm(), 2.0, 1e-12);
  EXPECT_NEAR(law.estimate()(0) / law.estimate()(1), 0.75, 1e-12);
}
