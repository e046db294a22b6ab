// The oracle yardstick (oracle/oracle_preadaptation.hpp): an onset at the first sample and at
// every change of the true theta, and nowhere else; theta_hat := the true theta at each; its
// phase cost the integral of |e|.
#include <gtest/gtest.h>

#include "preadaptive_mrac/core/control/event.hpp"
#include "preadaptive_mrac/core/control/oracle/oracle_preadaptation.hpp"

using namespace preadaptive_mrac;

namespace {

Sample sampleAt(double t, const Vec& theta, double e = 0.0) {
  static Vec x = Vec::Zero(3);
  Sample s;
  s.t = t;
  s.x = &x;
  s.theta_true = &theta;
  s.e = e;
  return s;
}

}  // namespace

TEST(OraclePreadaptation, AnOnsetAtTheStartAndAtEachSwitchOnly) {
  OraclePreadaptation oracle(0.001);
  EXPECT_TRUE(oracle.needsTruth());
  const Vec a = Vec::Constant(3, 0.1), b = Vec::Constant(3, 2.0);
  Vec theta_hat = Vec::Zero(3);
  std::vector<double> onsets;
  const double switches[] = {0.0, 0.005, 0.012};  // a, then b, then a again
  for (int k = 0; k < 20; ++k) {
    const double t = 0.001 * k;
    const Vec& theta = (t >= switches[1] && t < switches[2]) ? b : a;
    if (oracle.detect(sampleAt(t, theta), theta_hat, nullptr) == Detection::kOnset) {
      onsets.push_back(t);
      Event ev;
      oracle.onOnset(sampleAt(t, theta), &theta_hat, &ev);
      EXPECT_TRUE(ev.reset);
      EXPECT_EQ(theta_hat, theta) << "at t = " << t;
    }
  }
  ASSERT_EQ(onsets.size(), 3u);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(onsets[i], switches[i], 1e-12);
  // After a reset it starts again from the first sample.
  oracle.reset();
  EXPECT_EQ(oracle.detect(sampleAt(0.0, a), theta_hat, nullptr), Detection::kOnset);
}

TEST(OraclePreadaptation, PhaseCostIsTheIntegralOfTheAbsoluteError) {
  OraclePreadaptation oracle(0.01);
  const Vec a = Vec::Constant(3, 0.1);
  Vec theta_hat = Vec::Zero(3);
  Event onset;
  oracle.onOnset(sampleAt(0.0, a), &theta_hat, &onset);
  for (double e : {0.002, -0.003, 0.001}) oracle.duringPhase(sampleAt(0.0, a, e), 0.0, theta_hat);
  Event rec;
  oracle.onRecovery(sampleAt(0.03, a), theta_hat, &rec);
  EXPECT_NEAR(rec.cost, 0.01 * (0.002 + 0.003 + 0.001), 1e-15);
  // A new onset starts a new integral.
  oracle.onOnset(sampleAt(0.04, a), &theta_hat, &onset);
  EXPECT_EQ(oracle.phaseCost(), 0.0);
}
