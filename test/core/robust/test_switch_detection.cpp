// pa_robust's detection on numbers (switch_detection.hpp), no closed loop: the noise level from
// the change of the residual between windows, and the trigger rules.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "preadaptive_mrac/core/robust/switch_detection.hpp"

using namespace preadaptive_mrac;

namespace {

DetectionSettings settings() {
  DetectionSettings s;
  s.threshold = 0.005;
  s.noise_factor = 4.0;
  s.window_time = 0.5;
  s.noise_time = 20.0;
  s.detect_window = 50;
  s.long_window = 400;
  s.min_dwell = 100;
  s.quiet = 3;
  return s;
}

// Far from any onset or verification, with the long window full.
DetectionClock steadyClock() {
  DetectionClock c;
  c.since_onset = c.since_verified = 100000;
  c.stored = 1000;
  return c;
}

NoiseEstimate knownNoise(double mean_change) {
  NoiseEstimate n;
  n.mean_change = mean_change;
  n.started = true;
  n.blocks = kMinNoiseBlocks;
  return n;
}

}  // namespace

TEST(NoiseEstimate, LevelOfGaussianResidualsIsTheirStandardDeviation) {
  // Window residuals of standard deviation sigma: the estimate from their changes reads sigma.
  std::mt19937 gen(5);
  const double sigma = 0.002;
  std::normal_distribution<double> noise(0.0, sigma);
  NoiseEstimate est;
  double previous = noise(gen);
  const DetectionSettings s = settings();
  for (int i = 0; i < 20000; ++i) {
    const double now = noise(gen);
    est = foldNoiseChange(est, std::abs(now - previous), s.window_time, 1000.0, s.threshold);
    previous = now;
  }
  EXPECT_EQ(est.blocks, 20000);
  EXPECT_NEAR(est.level(), sigma, 0.03 * sigma);
}

TEST(NoiseEstimate, FirstChangeAsIsThenARunningMeanThenClipped) {
  NoiseEstimate est = foldNoiseChange(NoiseEstimate(), 0.004, 0.5, 20.0, 0.001);
  EXPECT_TRUE(est.started);
  EXPECT_DOUBLE_EQ(est.mean_change, 0.004);
  est = foldNoiseChange(est, 0.002, 0.5, 20.0, 0.001);  // the mean of two
  EXPECT_DOUBLE_EQ(est.mean_change, 0.003);
  // A switch's jump counts at most four times the estimate: (0.003 * 2 + 0.012) / 3.
  est = foldNoiseChange(est, 1.0, 0.5, 20.0, 0.001);
  EXPECT_DOUBLE_EQ(est.mean_change, 0.006);
  // After many blocks the weight is window_time / noise_time.
  NoiseEstimate late = knownNoise(0.004);
  late.blocks = 1000;
  late = foldNoiseChange(late, 0.008, 0.5, 20.0, 0.001);
  EXPECT_DOUBLE_EQ(late.mean_change, 0.004 + 0.025 * 0.004);
}

TEST(SwitchDetection, NoTriggerBeforeTheNoiseLevelIsKnown) {
  const DetectionSettings s = settings();
  Residuals rho;
  rho.detect = 1.0;  // far over any threshold
  NoiseEstimate young = knownNoise(0.0);
  young.blocks = kMinNoiseBlocks - 2;
  EXPECT_EQ(detectSwitch(rho, young, steadyClock(), 0, s).kind, Detection::kNone);
  // The block folded in this sample counts.
  young.blocks = kMinNoiseBlocks - 1;
  DetectionClock c = steadyClock();
  c.noise_due = true;
  rho.previous = 1.0;
  EXPECT_EQ(detectSwitch(rho, young, c, 0, s).kind, Detection::kOnset);
}

TEST(SwitchDetection, ShortWindowOnsetOverTheNoiseRaisedThreshold) {
  const DetectionSettings s = settings();
  // Noise level 0.002: threshold max(0.005, 4 * 0.002) = 0.008.
  const NoiseEstimate noise = knownNoise(0.002 * kMeanChangePerSigma);
  EXPECT_NEAR(shortThreshold(s, noise.level()), 0.008, 1e-15);
  Residuals rho;
  rho.detect = -0.0079;
  EXPECT_EQ(detectSwitch(rho, noise, steadyClock(), 0, s).kind, Detection::kNone);
  rho.detect = -0.0081;
  const DetectionResult r = detectSwitch(rho, noise, steadyClock(), 0, s);
  EXPECT_EQ(r.kind, Detection::kOnset);
  EXPECT_FALSE(r.long_trigger);
  // Not within min_dwell of the last onset.
  DetectionClock c = steadyClock();
  c.since_onset = s.min_dwell - 1;
  EXPECT_EQ(detectSwitch(rho, noise, c, 0, s).kind, Detection::kNone);
}

TEST(SwitchDetection, TheShortThresholdIsTheOneBeforeThisSamplesNoiseBlock) {
  const DetectionSettings s = settings();
  const NoiseEstimate noise = knownNoise(0.002 * kMeanChangePerSigma);  // threshold 0.008
  DetectionClock c = steadyClock();
  c.noise_due = true;
  Residuals rho;
  rho.detect = 0.0085;
  rho.previous = -0.0085;  // a change that raises the estimate above 0.0085 / 4
  const DetectionResult r = detectSwitch(rho, noise, c, 0, s);
  EXPECT_GT(shortThreshold(s, r.noise.level()), 0.0085);
  EXPECT_EQ(r.kind, Detection::kOnset);
  EXPECT_EQ(r.noise.blocks, kMinNoiseBlocks + 1);
}

TEST(SwitchDetection, LongWindowCatchesWhatTheShortOneMisses) {
  const DetectionSettings s = settings();
  const NoiseEstimate noise = knownNoise(0.002 * kMeanChangePerSigma);
  // Long threshold: max(0.005, 4 * 0.002 * 50 / 400) = 0.005.
  EXPECT_NEAR(longThreshold(s, noise.level()), 0.005, 1e-15);
  Residuals rho;
  rho.detect = 0.006;
  rho.long_window = 0.0051;
  DetectionResult r = detectSwitch(rho, noise, steadyClock(), 0, s);
  EXPECT_EQ(r.kind, Detection::kOnset);
  EXPECT_TRUE(r.long_trigger);
  // Not while the long window still holds data from before the last verification.
  DetectionClock c = steadyClock();
  c.since_verified = s.long_window - 1;
  EXPECT_FALSE(longWindowDue(s, c));
  EXPECT_EQ(detectSwitch(rho, noise, c, 0, s).kind, Detection::kNone);
  // Nor before it is full, nor without a long window.
  c = steadyClock();
  c.stored = s.long_window - 1;
  EXPECT_FALSE(longWindowDue(s, c));
  DetectionSettings no_long = s;
  no_long.long_window = 0;
  EXPECT_FALSE(longWindowDue(no_long, steadyClock()));
}

TEST(SwitchDetection, RecoveryAfterQuietSamplesInAPhase) {
  const DetectionSettings s = settings();
  const NoiseEstimate noise = knownNoise(0.0);
  DetectionClock c = steadyClock();
  Residuals rho;
  rho.detect = 0.001;
  // Outside a phase the count stays.
  EXPECT_EQ(detectSwitch(rho, noise, c, 1, s).quiet, 1);
  c.phase_active = true;
  int quiet = 0;
  DetectionResult r;
  for (int i = 0; i < s.quiet; ++i) {
    r = detectSwitch(rho, noise, c, quiet, s);
    quiet = r.quiet;
  }
  EXPECT_EQ(r.kind, Detection::kRecovered);
  // A loud sample (within min_dwell, so no onset) starts the count again.
  c.since_onset = 1;
  rho.detect = 0.006;
  r = detectSwitch(rho, noise, c, 2, s);
  EXPECT_EQ(r.kind, Detection::kNone);
  EXPECT_EQ(r.quiet, 0);
}

TEST(SwitchDetection, WhileVerifyingOnlyDecisionsAndTheNoiseEstimatePauses) {
  const DetectionSettings s = settings();
  const NoiseEstimate noise = knownNoise(0.002);
  DetectionClock c = steadyClock();
  c.verifying = true;
  c.noise_due = true;
  Residuals rho;
  rho.detect = 1.0;
  rho.previous = -1.0;
  DetectionResult r = detectSwitch(rho, noise, c, 0, s);
  EXPECT_EQ(r.kind, Detection::kNone);
  EXPECT_EQ(r.noise.blocks, noise.blocks);
  EXPECT_EQ(r.noise.mean_change, noise.mean_change);
  c.decision_due = true;
  EXPECT_EQ(detectSwitch(rho, noise, c, 0, s).kind, Detection::kDecision);
  EXPECT_FALSE(longWindowDue(s, c));
}

namespace {
// The cumulative residual an onset sees, newest sample first: a mismatch of `step` per sample
// for the `m` newest samples, a bias of `bias` per sample before, and the telescoped endpoint
// noise: S_J = sum of the J newest residuals = signal + eta_0 - eta_J.
std::vector<double> cumulativeResidual(int n, int m, double step, double bias, double sigma,
                                       unsigned seed) {
  std::mt19937 gen(seed);
  std::normal_distribution<double> eta(0.0, sigma);
  std::vector<double> e(static_cast<size_t>(n) + 1);
  for (double& v : e) v = eta(gen);
  std::vector<double> S(static_cast<size_t>(n));
  for (int J = 1; J <= n; ++J)
    S[static_cast<size_t>(J - 1)] =
        step * std::min(J, m) + bias * std::max(0, J - m) + e[0] - e[static_cast<size_t>(J)];
  return S;
}
}  // namespace

TEST(ChangePoint, BothRulesFindACleanChange) {
  // Without noise the kink is exact; the excursion rule leaves out up to a tenth of the change.
  const std::vector<double> S = cumulativeResidual(400, 40, 2.5e-5, 0.0, 0.0, 1);
  EXPECT_EQ(kinkChangePoint(S.data(), 400, 0.0), 40);
  EXPECT_EQ(excursionChangePoint(S.data(), 400), 36);
  // A jump in the newest sample alone (a large switch the short window sees at once): at least
  // two samples, as the excursion rule takes, not a kink far back in what came before.
  std::vector<double> jump = cumulativeResidual(400, 1, 3e-4, 0.0, 0.0, 1);
  for (int J = 2; J <= 400; ++J) jump[static_cast<size_t>(J - 1)] += 1e-8 * std::sin(0.05 * J);
  EXPECT_EQ(kinkChangePoint(jump.data(), 400, 0.0), 2);
}

TEST(ChangePoint, TheKinkFindsTheChangeInEndpointNoise) {
  // The long window's case (pa_robust at 0.1 mrad noise): 36 post-change samples of a 25 mrad
  // mismatch (2.5e-5 per 1 ms sample) among 400, endpoint noise 1.3e-4 (the whole change is
  // 7 such). The largest excursion holds the noise's peak as well, so 90 % of it lies before
  // the change in most draws; the kink stays near it.
  int kink_near = 0, excursion_near = 0, excursion_early = 0;
  for (unsigned seed = 1; seed <= 200; ++seed) {
    const std::vector<double> S = cumulativeResidual(400, 36, 2.5e-5, 0.0, 1.3e-4, seed);
    const int kink = kinkChangePoint(S.data(), 400, 9.0 * 1.3e-4 * 1.3e-4);
    const int exc = excursionChangePoint(S.data(), 400);
    kink_near += std::abs(kink - 36) <= 12;
    excursion_near += std::abs(exc - 36) <= 12;
    excursion_early += exc > 80;
  }
  EXPECT_GE(kink_near, 180);
  EXPECT_LE(excursion_near, 100);
  EXPECT_GE(excursion_early, 50);
}

TEST(ChangePoint, TheKinkAllowsTheOldEstimatesBias) {
  // Before the change the old estimate explained the data only nearly: a small slope of its own.
  const std::vector<double> S = cumulativeResidual(400, 50, 2.0e-5, 2.0e-6, 0.0, 1);
  EXPECT_EQ(kinkChangePoint(S.data(), 400, 0.0), 50);
}

TEST(ChangePoint, NoKinkBeyondNoiseIsAWholeSpanAfterTheChange) {
  // A mismatch that began before the span (a long-window trigger late after a small switch):
  // the residual grows alike at every J, with endpoint noise; no kink explains more than the
  // noise does, so the whole span is post-change. Without the noise bound a kink fitted to the
  // noise would keep a few samples only.
  int whole = 0, without_bound_short = 0;
  for (unsigned seed = 1; seed <= 100; ++seed) {
    const std::vector<double> S = cumulativeResidual(400, 400, 2.0e-6, 0.0, 1.3e-4, seed);
    whole += kinkChangePoint(S.data(), 400, 9.0 * 1.3e-4 * 1.3e-4) == 400;
    without_bound_short += kinkChangePoint(S.data(), 400, 0.0) < 200;
  }
  EXPECT_GE(whole, 95);
  EXPECT_GE(without_bound_short, 30);
  // A residual that grows alike everywhere, without noise: no kink at all.
  std::vector<double> line(100);
  for (int J = 1; J <= 100; ++J) line[static_cast<size_t>(J - 1)] = 1e-5 * J;
  EXPECT_EQ(kinkChangePoint(line.data(), 100, 0.0), 100);
}

TEST(ChangePoint, TooFewSamplesForAKinkTakeTheExcursion) {
  const std::vector<double> few = {1e-5, 2e-5, 3e-5, 3e-5, 3e-5};
  EXPECT_EQ(kinkChangePoint(few.data(), 5, 0.0), excursionChangePoint(few.data(), 5));
  EXPECT_EQ(excursionChangePoint(few.data(), 5), 3);
}
