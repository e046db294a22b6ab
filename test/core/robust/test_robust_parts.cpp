// pa_robust's parts on numbers, no closed loop (each case runs in microseconds): the chunk
// sums and the ridge fit (chunk_sums.hpp), the loss-of-effectiveness estimate
// (loss_estimate.hpp) and the decision (regime_decision.hpp), with one decision of a real run
// replayed from its numbers.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "preadaptive_mrac/core/robust/chunk_sums.hpp"
#include "preadaptive_mrac/core/robust/loss_estimate.hpp"
#include "preadaptive_mrac/core/robust/regime_decision.hpp"

using namespace preadaptive_mrac;

namespace {

Vec vec3(double a, double b, double c) {
  Vec v(3);
  v << a, b, c;
  return v;
}

// A window of `count` samples: phi_k a fixed pattern, y_k = theta^T phi_k (+ nu v_k).
IdentificationWindow windowOf(const Vec& theta, int count, double nu = 0.0) {
  IdentificationWindow win;
  win.resize(count + 2, 0, 3);
  for (int k = 0; k < count; ++k) {
    const Vec phi = vec3(0.001 * std::sin(0.3 * k), 0.002 * std::cos(0.17 * k), 0.0005 * (k % 7));
    const double v = -0.001 * std::cos(0.05 * k);
    win.push(phi, theta.dot(phi) + nu * v, Vec::Zero(3), v);
  }
  return win;
}

ChunkSums chunksOf(const IdentificationWindow& win, int len, bool with_loss) {
  ChunkSums s;
  s.clear(3);
  for (int j0 = win.count() - len; j0 >= 0; j0 -= len) s.add(win, j0, len, with_loss);
  return s;
}

// Noise-free data of theta over 60 samples in chunks of 10.
DecisionData dataOf(const Vec& theta) {
  const IdentificationWindow win = windowOf(theta, 60);
  DecisionData data;
  data.chunks = chunksOf(win, 10, false);
  win.sums(0, 60, &data.phi_tot, &data.y_tot);
  return data;
}

DecisionSettings settings(double sigma, double z, double margin, double prior_std, double ridge,
                          bool first_move = false, bool clip = false) {
  return {sigma, z, margin, prior_std, ridge, first_move, clip};
}

}  // namespace

TEST(ChunkSums, ErrorIsTheSumOfSquaredChunkResiduals) {
  const Vec truth = vec3(0.5, -1.0, 2.0);
  const IdentificationWindow win = windowOf(truth, 40, 0.3);
  const ChunkSums s = chunksOf(win, 10, true);
  const Vec th = vec3(0.4, -0.7, 1.0);
  double direct = 0.0, direct_nu = 0.0;
  const double nu = 0.3;
  for (int j0 = 30; j0 >= 0; j0 -= 10) {
    Vec Phi;
    double Y = 0.0;
    win.sums(j0, 10, &Phi, &Y);
    const double V = win.vSum(j0, 10);
    direct += std::pow(Y - th.dot(Phi), 2);
    direct_nu += std::pow(Y - (1.0 - nu) * th.dot(Phi) - nu * V, 2);
  }
  ASSERT_GT(direct, 1e-12);
  EXPECT_NEAR(s.error(th), direct, 1e-12 * direct);
  EXPECT_NEAR(s.error(th, nu), direct_nu, 1e-9 * direct);
  EXPECT_EQ(s.error(th, 0.0), s.error(th));
  // The data reads y = truth^T phi + nu v: the fixed point th = truth / (1 - nu) of
  // y = (1 - nu) th^T phi + nu V explains it.
  EXPECT_LT(s.error(truth / (1.0 - nu), nu), 1e-12 * s.c);
}

TEST(ChunkSums, RidgeFitFollowsExcitedDirectionsOnly) {
  // G = diag(4, 0, 1): the second direction carries no data. lambda = sigma^2 / prior_std^2 +
  // ridge trace(G) = 0.25 / 0.25 + 0.2 * 5 = 2.
  Mat G = Mat::Zero(3, 3);
  G(0, 0) = 4.0;
  G(2, 2) = 1.0;
  const Vec truth = vec3(1.0, 5.0, -3.0);
  const Vec base = vec3(0.0, 0.5, 0.0);
  const Vec fit = ridgeFit(G, G * truth, base, 0.5, 0.5, 0.2);
  EXPECT_NEAR(fit[0], 4.0 / 6.0, 1e-15);  // base + 4 / (4 + 2) (truth - base)
  EXPECT_EQ(fit[1], 0.5);                 // the base
  EXPECT_NEAR(fit[2], -1.0, 1e-15);       // 1 / (1 + 2) of the way
}

TEST(LossEstimate, RecoversTheLossFromNoiseFreeBlocksAndOnlyAfterFourBlocks) {
  // y = c^T phi + nu v over a square wave that flips every 10 samples; v carries the wave.
  const double nu = 0.35;
  const Vec c = vec3(0.2, -0.4, 1.5);
  LossEstimate est(3);
  est.restart(0);
  auto sample = [&](int k) {
    const std::int64_t half = k / 10;
    const double e = half % 2 == 0 ? 0.01 : -0.01;
    const Vec phi = vec3(0.001 * std::sin(0.07 * k), 0.001 * std::cos(0.11 * k), 0.0002 * (k % 3));
    const double v = -e * 0.02 + 0.0001 * std::sin(0.5 * k);
    est.add(k, half, phi, c.dot(phi) + nu * v, v, e * 0.02);
  };
  for (int k = 0; k < 40; ++k) sample(k);
  // Flips at 10, 20, 30: the first block joins at the second flip, the next at the third.
  EXPECT_EQ(est.blocks(), 2);
  EXPECT_EQ(est.fit(1e-4).first, 0.0);
  EXPECT_EQ(est.fit(1e-4).second, 0.0);
  for (int k = 40; k < 120; ++k) sample(k);
  EXPECT_EQ(est.blocks(), 10);  // flips at 10 .. 110, less the one still pending
  const std::pair<double, double> f = est.fit(1e-4);
  EXPECT_NEAR(f.first, nu, 1e-9);
  ASSERT_GT(f.second, 0.0);
  // The information scales as 1 / sigma^2.
  EXPECT_NEAR(est.fit(2e-4).second, f.second / 4.0, 1e-9 * f.second);
  // Blocks that began before the restart's sample never join.
  est.restart(115);
  for (int k = 120; k < 150; ++k) sample(k);
  EXPECT_EQ(est.blocks(), 1);  // the block of 120 (opened at that flip) joined at 140
}

TEST(RegimeDecision, RecallsTheRememberedRegimeThatExplainsTheData) {
  const Vec truth = vec3(-1.0, 3.0, 0.5);
  const DecisionData data = dataOf(truth);
  DecisionCandidates cand;
  cand.keep = vec3(0.1, 0.1, 0.1);
  cand.memory = {vec3(2.0, 2.0, 2.0), truth};
  cand.memory_loss = {0.0, 0.0};
  cand.use_network = true;
  cand.network = vec3(0.0, 0.0, 0.0);
  const DecisionSettings s = settings(1e-6, 3.0, 0.1, 1.0, 1e-6);
  const DecisionResult r = decideRegime(data, cand, s);
  EXPECT_EQ(r.kind, Event::Decision::kMemory);
  EXPECT_EQ(r.chosen, 1);
  EXPECT_EQ(r.candidates, 4);  // keep, two remembered, the network
  EXPECT_EQ(r.theta, truth);   // explains the data: used as remembered, no fit
  EXPECT_GT(r.error_keep, 0.0);
  // Keeping the truth: nothing beats it, nothing moves.
  cand.keep = truth;
  const DecisionResult k = decideRegime(data, cand, s);
  EXPECT_EQ(k.kind, Event::Decision::kKeep);
  EXPECT_EQ(k.chosen, -1);
  EXPECT_EQ(k.theta, truth);
}

TEST(RegimeDecision, FitsWhenNoCandidateExplainsAndClipsTheFirstMove) {
  const DecisionData data = dataOf(vec3(-1.0, 3.0, 0.5));
  DecisionCandidates cand;
  cand.keep = vec3(0.0, 0.0, 0.0);
  DecisionSettings s = settings(1e-6, 3.0, 0.1, 10.0, 0.0);
  DecisionResult r = decideRegime(data, cand, s);
  EXPECT_EQ(r.kind, Event::Decision::kFit);
  EXPECT_EQ(r.candidates, 1);
  EXPECT_LT(data.chunks.error(r.theta), 1e-6 * r.error_keep);
  // Re-made later (clip) and the first move: the mean mismatch moves to z sigma short of the
  // data, no further.
  s.clip = true;
  s.first_move = true;
  r = decideRegime(data, cand, s);
  EXPECT_EQ(r.kind, Event::Decision::kFit);
  EXPECT_NEAR(std::abs(data.y_tot - r.theta.dot(data.phi_tot)), s.z * s.sigma, 1e-15);
}

TEST(RegimeDecision, ReplaysARealRecallWithItsLoss) {
  // The first decision after the switch at 32.605 s back to a regime seen before (Lambda
  // 0.847, nu = 0.153), in a real run: preadapt_family --seed 90210 --count 1 --modes pa_robust
  // --effectiveness 0.4:1.0 --out-dir D, then preadapt_sim --scenario D/scenario_0.yaml
  // --mode pa_robust --set plant.noise.std=[1e-4,1e-4,0], its decision at sample 32610, the
  // numbers printed with %.17g. Remembered regime 1 carries a loss of 0.1527 from its earlier
  // visit; it is recalled with it, and this first move is clipped to what the data proves.
  DecisionData data;
  ChunkSums& cs = data.chunks;
  cs.clear(3);
  cs.G << 1.6081984582887171e-06, -6.3451670905790547e-07, -2.2676359023751209e-07,
      -6.3451670905790547e-07, 2.5034935955733547e-07, 8.9469857572659154e-08,
      -2.2676359023751209e-07, 8.9469857572659154e-08, 3.1974738933728433e-08;
  cs.h = vec3(4.1979487404049676e-06, -1.6563059153718797e-06, -5.9193063088757897e-07);
  cs.c = 1.0958083895827159e-05;
  cs.loss.hv = vec3(2.1226124651624063e-06, -8.3747939755725307e-07, -2.9929839865367586e-07);
  cs.loss.yv = 5.5407454711641682e-06;
  cs.loss.vv = 2.8015719415979978e-06;
  cs.loss.v = -0.0016737896945548439;
  data.phi_tot = vec3(-0.0012681476484576696, 0.0005003492375904409, 0.00017881481743336718);
  data.y_tot = -0.0033102996685839725;
  DecisionCandidates cand;
  cand.keep = vec3(0.81170644538109726, -1.240516858230994, -0.08410269974017183);
  cand.memory = {vec3(0.045397723188261081, 0.0094898301909287358, -0.015433612052884554),
                 vec3(2.4201155952150168, -1.8725557577251817, -0.49596680430136453),
                 vec3(0.81170644538109726, -1.240516858230994, -0.08410269974017183)};
  cand.memory_loss = {0.0, 0.15266860506725188, 0.062186711766754318};
  cand.use_network = true;
  cand.network = vec3(0.47374856941171406, -1.1053850355395101, 0.017356091794759304);
  const DecisionSettings s = settings(3.2141343921091869e-06, 3.0, 0.2, 1.0, 0.01, true, true);
  const DecisionResult r = decideRegime(data, cand, s);
  EXPECT_EQ(r.kind, Event::Decision::kMemory);
  EXPECT_EQ(r.chosen, 1);
  EXPECT_EQ(r.candidates, 5);
  EXPECT_EQ(r.nu, 0.15266860506725188);
  EXPECT_EQ(r.error_keep, 2.7067013856639909e-06);
  // The run's estimate, to the bit.
  EXPECT_EQ(r.theta[0], 2.0852794989014845);
  EXPECT_EQ(r.theta[1], -1.7404457579850132);
  EXPECT_EQ(r.theta[2], -0.4487533307715158);
}
