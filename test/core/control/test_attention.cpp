// Attention function and velocity estimator on synthetic e(t).
#include <gtest/gtest.h>

#include <vector>

#include "preadaptive_mrac/core/controller/controller.hpp"

using namespace preadaptive_mrac;
using R = Attention::Result;

namespace {
constexpr double kDt = 0.001;

// Feed e(t) through the velocity estimator and the attention function; collect results.
std::vector<std::pair<double, R>> run(const std::function<double(double)>& e, double t_end,
                                      double c_e = 0.005, double c_ed = 0.02, double tau = 0.01) {
  VelocityEstimator vel(tau, kDt);
  Attention att(c_e, c_ed);
  std::vector<std::pair<double, R>> out;
  for (int k = 0; k * kDt < t_end; ++k) {
    const double t = k * kDt;
    const double ek = e(t);
    const R r = att.update(ek, vel.update(ek));
    if (r != R::kNone) out.push_back({t, r});
  }
  return out;
}
}  // namespace

TEST(VelocityEstimator, TracksARampAndStartsAtZero) {
  VelocityEstimator v(0.01, kDt);
  EXPECT_EQ(v.update(0.3), 0.0);  // first sample: no history
  double est = 0.0;
  for (int k = 1; k <= 200; ++k) est = v.update(0.3 + 0.05 * k * kDt);
  EXPECT_NEAR(est, 0.05, 1e-6);     // after 20 time constants the lag is gone
  VelocityEstimator raw(0.0, kDt);  // tau = 0: plain backward difference
  raw.update(1.0);
  EXPECT_NEAR(raw.update(1.002), 2.0, 1e-9);
}

TEST(Attention, FastCrossingIsAnOnset) {
  // |e| rises through c_e at 0.05 rad/s > c_ed.
  const auto ev = run([](double t) { return 0.05 * t; }, 0.5);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].second, R::kOnset);
  EXPECT_NEAR(ev[0].first, 0.1, 2 * kDt);
  // Negative errors count by magnitude.
  const auto neg = run([](double t) { return -0.05 * t; }, 0.5);
  ASSERT_EQ(neg.size(), 1u);
  EXPECT_EQ(neg[0].second, R::kOnset);
}

TEST(Attention, SlowCrossingIsNothing) {
  // |e| rises through c_e at 0.01 rad/s < c_ed: no event at all.
  EXPECT_TRUE(run([](double t) { return 0.01 * t; }, 1.0).empty());
}

TEST(Attention, RecoveryOnlyInsideAPhase) {
  // Slow descent through c_e with no phase: reported as an ignored recovery.
  const auto ignored = run([](double t) { return 0.01 - 0.01 * t; }, 1.0);
  ASSERT_EQ(ignored.size(), 1u);
  EXPECT_EQ(ignored[0].second, R::kIgnoredRecovery);
  // Fast rise (onset), then a slow fall through c_e: recovered.
  const auto phase =
      run([](double t) { return t < 0.2 ? 0.05 * t : 0.01 - 0.005 * (t - 0.2); }, 2.0);
  ASSERT_EQ(phase.size(), 2u);
  EXPECT_EQ(phase[0].second, R::kOnset);
  EXPECT_EQ(phase[1].second, R::kRecovered);
  EXPECT_NEAR(phase[1].first, 1.2, 2 * kDt);
}

TEST(Attention, FastFallDoesNotEndAPhaseAndSecondOnsetIsIgnored) {
  // Fast up (onset), fast down (rate too high to count as recovery), fast up again (ignored
  // onset: the phase is still active), then slow down (recovered).
  const auto ev = run(
      [](double t) {
        if (t < 0.2) return 0.05 * t;                 // up to 0.01
        if (t < 0.4) return 0.01 - 0.05 * (t - 0.2);  // down to 0 fast
        if (t < 0.6) return 0.05 * (t - 0.4);         // up to 0.01 fast
        return 0.01 - 0.005 * (t - 0.6);              // slow fall
      },
      3.0);
  ASSERT_EQ(ev.size(), 3u);
  EXPECT_EQ(ev[0].second, R::kOnset);
  EXPECT_EQ(ev[1].second, R::kIgnoredOnset);
  EXPECT_EQ(ev[2].second, R::kRecovered);
}

TEST(Attention, SampleExactlyAtTheThreshold) {
  // s = |e| - c_e = 0 exactly counts as crossed from below (s_prev < 0 <= s) ...
  Attention a(0.005, 0.02);
  EXPECT_EQ(a.update(0.004, 0.0), R::kNone);  // first sample primes
  EXPECT_EQ(a.update(0.005, 0.03), R::kOnset);
  // ... and the next sample above it is no new crossing (s_prev = 0 is not < 0).
  EXPECT_EQ(a.update(0.006, 0.03), R::kNone);
  // From above, reaching exactly c_e with a slow rate is the recovery (s_prev > 0 >= s).
  EXPECT_EQ(a.update(0.005, -0.01), R::kRecovered);
  EXPECT_EQ(a.update(0.004, -0.01), R::kNone);
  EXPECT_FALSE(a.phaseActive());
  // Rate exactly at c_ed is not "> c_ed": no onset.
  Attention b(0.005, 0.02);
  b.update(0.004, 0.0);
  EXPECT_EQ(b.update(0.0055, 0.02), R::kNone);
}

TEST(Attention, FirstSampleNeverFires) {
  Attention a(0.005, 0.02);
  EXPECT_EQ(a.update(0.5, 10.0), R::kNone);
  EXPECT_FALSE(a.phaseActive());
}
