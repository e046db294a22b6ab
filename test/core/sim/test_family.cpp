// The recurring-regime scenario family and its report (docs/research/robust.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "preadaptive_mrac/core/sim/scenario_family.hpp"
#include "preadaptive_mrac/io/setup.hpp"
#include "preadaptive_mrac/io/yaml_params.hpp"

using namespace preadaptive_mrac;

TEST(Family, ShapeAndRecurrence) {
  FamilySpec spec;
  for (int k = 0; k < 50; ++k) {
    const Scenario s = recurringScenario(spec, 11, k);
    ASSERT_EQ(s.theta.size(), 1u + static_cast<size_t>(spec.segments));
    EXPECT_DOUBLE_EQ(s.theta[0].until, spec.first_duration);
    EXPECT_TRUE(s.theta[0].theta.isApprox(Eigen::VectorXd::Constant(3, 0.1)));
    std::map<std::vector<double>, int> visits;
    for (size_t i = 1; i < s.theta.size(); ++i) {
      const auto& th = s.theta[i].theta;
      const double d = s.theta[i].until - s.theta[i - 1].until;
      EXPECT_GE(d, spec.min_duration - 1e-3);
      EXPECT_LE(d, spec.max_duration + 1e-3);
      EXPECT_FALSE(th == s.theta[i - 1].theta) << "a regime twice in a row";
      EXPECT_GT(th.minCoeff(), spec.min_scale * (1.0 - spec.spread) - 1e-12);
      EXPECT_LT(th.maxCoeff(), spec.max_scale * (1.0 + spec.spread) + 1e-12);
      EXPECT_GT(th.maxCoeff() - th.minCoeff(), 0.0) << "components must differ";
      ++visits[std::vector<double>(th.data(), th.data() + th.size())];
    }
    EXPECT_EQ(visits.size(), static_cast<size_t>(spec.regimes));
    for (const auto& kv : visits) EXPECT_GE(kv.second, 2);
    const auto rep = repeatedWindows(s);
    int repeated = 0;
    for (bool b : rep) repeated += b;
    EXPECT_EQ(repeated, spec.segments - spec.regimes);
  }
}

TEST(Family, NegativeScalesStayInTheirRange) {
  FamilySpec spec;
  spec.min_scale = -0.6;
  spec.max_scale = -0.15;
  double lo = 0.0, hi = -1.0;
  for (int k = 0; k < 50; ++k) {
    const Scenario s = recurringScenario(spec, 11, k);
    EXPECT_TRUE(s.theta[0].theta.isApprox(Eigen::VectorXd::Constant(3, 0.1)));
    for (size_t i = 1; i < s.theta.size(); ++i) {
      const auto& th = s.theta[i].theta;
      EXPECT_LT(th.maxCoeff(), spec.max_scale * (1.0 - spec.spread) + 1e-12);
      EXPECT_GT(th.minCoeff(), spec.min_scale * (1.0 + spec.spread) - 1e-12);
      lo = std::min(lo, th.mean());
      hi = std::max(hi, th.mean());
    }
  }
  EXPECT_LT(lo, -0.45);  // the draws cover the range
  EXPECT_GT(hi, -0.25);
}

TEST(Family, DeterministicAndSeedDependent) {
  FamilySpec spec;
  const Scenario a = recurringScenario(spec, 5, 3), b = recurringScenario(spec, 5, 3);
  const Scenario c = recurringScenario(spec, 6, 3), d = recurringScenario(spec, 5, 4);
  EXPECT_EQ(scenarioToYaml(a), scenarioToYaml(b));
  EXPECT_NE(scenarioToYaml(a), scenarioToYaml(c));
  EXPECT_NE(scenarioToYaml(a), scenarioToYaml(d));
}

TEST(Family, ConditionDrawsStayInTheirRangeAndAreDeterministic) {
  const ConditionRange r{0.02, 0.08};
  double lo = 1.0, hi = 0.0;
  for (int k = 0; k < 200; ++k) {
    const double v = drawCondition(r, 77, k, 2);
    EXPECT_GE(v, r.lo);
    EXPECT_LE(v, r.hi);
    EXPECT_EQ(v, drawCondition(r, 77, k, 2));  // the same scenario, the same value
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  EXPECT_LT(lo, 0.03);  // spread over the range, not stuck at one end
  EXPECT_GT(hi, 0.07);
  EXPECT_NE(drawCondition(r, 77, 0, 2), drawCondition(r, 78, 0, 2));  // the family seed
  EXPECT_NE(drawCondition(r, 77, 0, 1), drawCondition(r, 77, 0, 2));  // each condition its own
  EXPECT_EQ(drawCondition({0.05, 0.05}, 77, 3, 1), 0.05);             // one value: no draw
}

TEST(Family, EffectivenessPerRegimeFirstSegmentOne) {
  FamilySpec spec;
  const ConditionRange r{0.4, 1.0};
  for (int k = 0; k < 20; ++k) {
    const Scenario s = recurringScenario(spec, 77, k);
    const auto eff = regimeEffectiveness(s, r, 77, k);
    ASSERT_EQ(eff.size(), s.theta.size());
    EXPECT_EQ(eff[0].value, 1.0);
    std::map<std::vector<double>, double> of;
    for (size_t i = 0; i < s.theta.size(); ++i) {
      EXPECT_EQ(eff[i].until, s.theta[i].until);
      if (i == 0) continue;
      EXPECT_GE(eff[i].value, r.lo);
      EXPECT_LE(eff[i].value, r.hi);
      const auto& th = s.theta[i].theta;
      const auto key = std::vector<double>(th.data(), th.data() + th.size());
      if (of.count(key) == 0) of[key] = eff[i].value;
      EXPECT_EQ(of[key], eff[i].value) << "a revisited regime, another Lambda";
    }
    EXPECT_EQ(of.size(), static_cast<size_t>(spec.regimes));
    EXPECT_EQ(scenarioToYaml(s), scenarioToYaml(recurringScenario(spec, 77, k)));  // untouched
    const auto again = regimeEffectiveness(s, r, 77, k);
    for (size_t i = 0; i < eff.size(); ++i) EXPECT_EQ(again[i].value, eff[i].value);
  }
}

namespace {

// A scenario written as preadapt_family --out-dir writes it and read back as a scenario file
// (3 states); a file the reader refuses fails the test.
Scenario readBack(const Scenario& s) {
  const ParamValue tree = parseYaml(scenarioToYaml(s), "family");
  ParamReader r(tree);
  Scenario back = Scenario::read(r, 3);
  EXPECT_TRUE(r.ok()) << ConfigError(r.problems()).what();
  return back;
}

}  // namespace

// --faults draws one set of physical faults per regime (the first segment nominal),
// each key within its range, deterministic per (seed, scenario); a key given as one value is
// that value in every regime, a key not given stays nominal; the schedule reads back from YAML.
TEST(Family, FaultsPerRegimeInRangeDeterministically) {
  FamilySpec spec;
  FaultRanges ranges;
  ranges.range[0] = {-0.05, 0.1};  // cg_shift
  ranges.range[1] = {0.5, 1.0};    // elevator_effectiveness
  // pitch_damping not given: nominal 1
  FaultRanges fixed;
  fixed.range[2] = {0.4, 0.4};  // pitch_damping, one value
  ASSERT_EQ(Scenario::kFaultKeys[0].name, std::string("cg_shift"));
  ASSERT_EQ(Scenario::kFaultKeys[1].name, std::string("elevator_effectiveness"));
  ASSERT_EQ(Scenario::kFaultKeys[2].name, std::string("pitch_damping"));
  double lo[2] = {1.0, 1.0}, hi[2] = {-1.0, -1.0};
  for (int k = 0; k < 30; ++k) {
    const Scenario s = recurringScenario(spec, 77, k);
    const auto f = regimeFaults(s, ranges, 77, k);
    ASSERT_EQ(f.size(), s.theta.size());
    EXPECT_EQ(f[0].cg_shift, 0.0);
    EXPECT_EQ(f[0].elevator_effectiveness, 1.0);
    EXPECT_EQ(f[0].pitch_damping, 1.0);
    std::map<std::vector<double>, std::vector<double>> of;
    for (size_t i = 0; i < s.theta.size(); ++i) {
      EXPECT_EQ(f[i].until, s.theta[i].until);
      if (i == 0) continue;
      const double v[2] = {f[i].cg_shift, f[i].elevator_effectiveness};
      for (int j = 0; j < 2; ++j) {
        EXPECT_GE(v[j], ranges.range[static_cast<size_t>(j)].lo);
        EXPECT_LE(v[j], ranges.range[static_cast<size_t>(j)].hi);
        lo[j] = std::min(lo[j], v[j]);
        hi[j] = std::max(hi[j], v[j]);
      }
      EXPECT_EQ(f[i].pitch_damping, 1.0) << "a key not given must stay nominal";
      EXPECT_NE(f[i].cg_shift, f[i].elevator_effectiveness);  // each key its own draw
      const auto& th = s.theta[i].theta;
      const auto key = std::vector<double>(th.data(), th.data() + th.size());
      const std::vector<double> val = {v[0], v[1]};
      if (of.count(key) == 0) of[key] = val;
      EXPECT_EQ(of[key], val) << "a revisited regime, other faults";
    }
    EXPECT_EQ(of.size(), static_cast<size_t>(spec.regimes)) << "regimes share their faults";
    const auto again = regimeFaults(s, ranges, 77, k);
    for (size_t i = 0; i < f.size(); ++i) {
      EXPECT_EQ(again[i].cg_shift, f[i].cg_shift);
      EXPECT_EQ(again[i].elevator_effectiveness, f[i].elevator_effectiveness);
    }
    const auto one = regimeFaults(s, fixed, 77, k);
    for (size_t i = 1; i < one.size(); ++i) {
      EXPECT_EQ(one[i].pitch_damping, 0.4);
      EXPECT_EQ(one[i].cg_shift, 0.0);
      EXPECT_EQ(one[i].elevator_effectiveness, 1.0);
    }
    EXPECT_EQ(one[0].pitch_damping, 1.0);
  }
  EXPECT_LT(lo[0], -0.02);  // spread over the ranges, not stuck at one end
  EXPECT_GT(hi[0], 0.07);
  EXPECT_LT(lo[1], 0.6);
  EXPECT_GT(hi[1], 0.9);
  const Scenario s = recurringScenario(spec, 77, 0);
  EXPECT_NE(regimeFaults(s, ranges, 77, 0)[1].cg_shift, regimeFaults(s, ranges, 78, 0)[1].cg_shift);
  EXPECT_NE(regimeFaults(s, ranges, 77, 0)[1].cg_shift, regimeFaults(s, ranges, 77, 1)[1].cg_shift);
  // The draw moves no other value of the family: the Lambdas per regime are their own streams.
  const ConditionRange lambda{0.4, 1.0};
  EXPECT_EQ(regimeEffectiveness(s, lambda, 77, 0)[1].value, drawCondition(lambda, 77, 0, 1000));
  // Written and read back exactly (preadapt_family --out-dir's scenario files).
  Scenario with = s;
  with.faults = regimeFaults(s, ranges, 77, 0);
  const Scenario back = readBack(with);
  ASSERT_EQ(back.faults.size(), with.faults.size());
  for (size_t i = 0; i < with.faults.size(); ++i) {
    EXPECT_EQ(back.faults[i].until, with.faults[i].until);
    for (const auto& f : Scenario::kFaultKeys)
      EXPECT_EQ(back.faults[i].*f.field, with.faults[i].*f.field) << f.name;
  }
}

TEST(Family, YamlReadsBackExactly) {
  FamilySpec spec;
  spec.ref_every = 7.0;
  const Scenario s = recurringScenario(spec, 3, 1);
  ASSERT_GT(s.reference.size(), 2u);
  const Scenario back = readBack(s);
  ASSERT_EQ(back.theta.size(), s.theta.size());
  for (size_t i = 0; i < s.theta.size(); ++i) {
    EXPECT_EQ(back.theta[i].until, s.theta[i].until);
    EXPECT_EQ(back.theta[i].theta, s.theta[i].theta);
  }
  ASSERT_EQ(back.reference.size(), s.reference.size());
  for (size_t i = 0; i < s.reference.size(); ++i) EXPECT_EQ(back.reference[i].r, s.reference[i].r);
}

TEST(Family, SummaryCountsOnlyRepeatedWindows) {
  // Two scenarios of 4 windows; windows 2 and 3 repeat in the first, only 3 in the second.
  const std::vector<std::vector<bool>> repeated = {{false, false, true, true},
                                                   {false, false, false, true}};
  std::vector<RunDigest> rac(2), mode(2), oracle(2);
  rac[0] = {{1, 1, 1, 1}, 10.0, 1.0};
  rac[1] = {{1, 1, 1, 1}, 10.0, 1.0};
  mode[0] = {{1, 9, 0.4, 0.8}, 10.6, 3.0};   // ratios 0.4 (halved) and 0.8; window 1 ignored
  mode[1] = {{1, 0.1, 0.1, 2.0}, 5.0, 2.0};  // ratio 2.0
  oracle[0] = {{1, 0, 0, 0}, 1.0, 2.5};
  oracle[1] = {{1, 0, 0, 0}, 1.0, 2.5};
  const FamilySummary s = summarizeFamily(repeated, rac, mode, &oracle);
  EXPECT_EQ(s.windows, 3);
  EXPECT_DOUBLE_EQ(s.frac_better, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.frac_halved, 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.median_ratio, 0.8);
  EXPECT_DOUBLE_EQ(s.worst_ratio, 2.0);
  EXPECT_DOUBLE_EQ(s.all_worst_ratio, 9.0);
  EXPECT_DOUBLE_EQ(s.worst_iae_ratio, 1.06);
  EXPECT_EQ(s.iae_over, 1);
  EXPECT_DOUBLE_EQ(s.worst_u_rac, 3.0);
  EXPECT_DOUBLE_EQ(s.worst_u_oracle, 1.2);
}

namespace {
// A scenario of hand-made segments, one per theta, 10 s each.
Scenario segmentsOf(const std::vector<Eigen::Vector3d>& thetas) {
  Scenario s;
  for (size_t i = 0; i < thetas.size(); ++i)
    s.theta.push_back({10.0 * static_cast<double>(i + 1), thetas[i]});
  return s;
}
}  // namespace

TEST(Family, NoisePeakIsTheBoundOfTheLargestExcursion) {
  // sigma sqrt(2 ln(2 n)): 4.55 sigma for 16000 samples; 16000 standard normal draws reach about
  // 4.0 on average, and rarely beyond the bound.
  EXPECT_NEAR(noisePeak(1.0, 16000.0), 4.555, 1e-3);
  EXPECT_DOUBLE_EQ(noisePeak(2.0, 16000.0), 2.0 * noisePeak(1.0, 16000.0));
  GaussianSource g(11);
  int beyond = 0;
  double mean = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    double top = 0.0;
    for (int i = 0; i < 16000; ++i) top = std::max(top, std::abs(g.next()));
    mean += top / 200.0;
    beyond += top > noisePeak(1.0, 16000.0);
  }
  EXPECT_NEAR(mean, 4.0, 0.15);
  EXPECT_LE(beyond, 20);
}

TEST(Family, AQuietWindowIsOneWhoseRacPeakTheNoiseCouldNearlyMake) {
  // Three windows of 10 s at 1 ms, 0.1 mrad of noise: the bound is 0.1 mrad x 4.45 = 0.445 mrad,
  // quiet up to twice that. Window 0 (no switch) never; without noise, or with factor 0, none.
  const Scenario s = segmentsOf(
      {Eigen::Vector3d::Constant(0.1), Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(4, 5, 6)});
  RunDigest rac;
  rac.peak = {1e-4, 0.88e-3, 0.90e-3};  // below and above 2 x 0.445
  const double bound = noisePeak(1e-4, 10000.0);
  ASSERT_NEAR(bound, 0.445e-3, 1e-6);
  EXPECT_EQ(quietWindows(s, 0.001, 1e-4, rac), (std::vector<bool>{false, true, false}));
  EXPECT_EQ(quietWindows(s, 0.001, 0.0, rac), (std::vector<bool>(3, false)));
  EXPECT_EQ(quietWindows(s, 0.001, 1e-4, rac, 0.0), (std::vector<bool>(3, false)));
  // A lost rac (peaks inf or NaN after its blow-up) has no quiet window there.
  rac.peak = {1e-4, INFINITY, std::nan("")};
  EXPECT_EQ(quietWindows(s, 0.001, 1e-4, rac), (std::vector<bool>(3, false)));
}

TEST(Family, QuietWindowsAreJudgedByNoRatio) {
  // The summary of SummaryCountsOnlyRepeatedWindows with the first scenario's window 3 quiet:
  // its ratio (0.8) leaves every statistic and is counted as quiet; window 1 (not repeated,
  // ratio 9) quiet as well leaves the all-window worst.
  const std::vector<std::vector<bool>> repeated = {{false, false, true, true},
                                                   {false, false, false, true}};
  const std::vector<std::vector<bool>> quiet = {{false, true, false, true},
                                                {false, false, false, false}};
  std::vector<RunDigest> rac(2), mode(2);
  rac[0] = {{1, 1, 1, 1}, 10.0, 1.0};
  rac[1] = {{1, 1, 1, 1}, 10.0, 1.0};
  mode[0] = {{1, 9, 0.4, 0.8}, 10.6, 3.0};
  mode[1] = {{1, 0.1, 0.1, 2.0}, 5.0, 2.0};
  const FamilySummary s = summarizeFamily(repeated, rac, mode, nullptr, &quiet);
  EXPECT_EQ(s.windows, 2);
  EXPECT_EQ(s.quiet, 1);
  EXPECT_DOUBLE_EQ(s.frac_better, 0.5);
  EXPECT_DOUBLE_EQ(s.median_ratio, 1.2);  // (0.4 + 2.0) / 2
  EXPECT_DOUBLE_EQ(s.worst_ratio, 2.0);
  EXPECT_DOUBLE_EQ(s.all_worst_ratio, 2.0);
  const FamilySummary all = summarizeFamily(repeated, rac, mode, nullptr);
  EXPECT_EQ(all.windows, 3);
  EXPECT_EQ(all.quiet, 0);
  // Revisits against the oracle leave the quiet ones out too.
  std::vector<RunDigest> oracle(2);
  oracle[0].peak = {1, 1, 0.4, 0.4};  // revisits 2 and 3 of the first: 1.0 and 2.0 (quiet)
  oracle[1].peak = {1, 1, 1, 1};
  const RevisitSummary rv = summarizeRevisits(repeated, oracle, mode, &quiet);
  EXPECT_EQ(rv.count, 2);
  EXPECT_DOUBLE_EQ(rv.worst, 2.0);  // the second scenario's window 3
  EXPECT_DOUBLE_EQ(rv.within, 0.5);
  EXPECT_EQ(summarizeRevisits(repeated, oracle, mode).count, 3);
  // A run lost in a quiet window (IAE not finite, its peak there NaN) counts there all the same.
  std::vector<RunDigest> lost = mode;
  lost[0].iae = std::nan("");
  lost[0].peak = {1, 1, 0.4, std::nan("")};
  const FamilySummary l = summarizeFamily(repeated, rac, lost, nullptr, &quiet);
  EXPECT_EQ(l.lost_runs, 1);
  EXPECT_EQ(l.quiet, 0);
  EXPECT_EQ(l.worst_ratio, HUGE_VAL);
  EXPECT_EQ(summarizeRevisits(repeated, oracle, lost, &quiet).worst, HUGE_VAL);
}

// Revisits are the windows switching back to a theta seen earlier in the scenario (the first
// segment's too); each is the mode's peak over the oracle's in that window. Every other window
// has a ratio far above any revisit's, so counting one of them moves the worst and the median.
TEST(Family, RevisitsComparePeaksWithTheOracleInTheSameWindow) {
  const Eigen::Vector3d first = Eigen::Vector3d::Constant(0.1), a(1, 2, 3), b(4, 5, 6), c(2, 2, 1),
                        d(7, 1, 1);
  const std::vector<Scenario> family = {segmentsOf({first, a, b, a, b}),
                                        segmentsOf({first, c, first, d, c})};
  std::vector<std::vector<bool>> repeated;
  for (const auto& s : family) repeated.push_back(repeatedWindows(s));
  std::vector<RunDigest> oracle(2), mode(2);
  oracle[0].peak = {1.0, 2.0, 2.0, 0.5, 0.4};
  oracle[1].peak = {1.0, 1.0, 0.2, 1.0, 0.1};
  mode[0].peak = {5.0, 9.0, 9.0, 0.55, 0.6};  // revisits 3 and 4: 1.1 and 1.5
  mode[1].peak = {1.0, 0.1, 0.2, 7.0, 0.13};  // revisits 2 and 4: 1.0 and 1.3
  const std::vector<RevisitRatio> one = revisitRatios(repeated[1], oracle[1], mode[1]);
  ASSERT_EQ(one.size(), 2u);
  EXPECT_EQ(one[0].window, 2);  // back to the first segment's theta
  EXPECT_DOUBLE_EQ(one[0].ratio, 1.0);
  EXPECT_EQ(one[1].window, 4);
  EXPECT_DOUBLE_EQ(one[1].ratio, 1.3);
  const RevisitSummary s = summarizeRevisits(repeated, oracle, mode);
  EXPECT_EQ(s.count, 4);
  ASSERT_EQ(s.ratios.size(), 4u);
  EXPECT_DOUBLE_EQ(s.ratios[0], 1.1);
  EXPECT_DOUBLE_EQ(s.ratios[1], 1.5);
  EXPECT_DOUBLE_EQ(s.median, 1.2);  // (1.1 + 1.3) / 2
  EXPECT_DOUBLE_EQ(s.worst, 1.5);
  EXPECT_DOUBLE_EQ(s.within, 0.5);  // 1.0 and 1.1 within 1.2x, 1.3 and 1.5 not
  // The oracle against itself: every revisit at 1.
  const RevisitSummary self = summarizeRevisits(repeated, oracle, oracle);
  EXPECT_EQ(self.count, 4);
  EXPECT_DOUBLE_EQ(self.worst, 1.0);
  EXPECT_DOUBLE_EQ(self.within, 1.0);
  // No revisit at all: nothing compared.
  const RevisitSummary none = summarizeRevisits({{false, false, false}}, oracle, mode);
  EXPECT_EQ(none.count, 0);
  EXPECT_EQ(none.within, 0.0);
}

// A run lost in window 3 (IAE NaN, the peaks after it 0): its revisits from there are the worst;
// the oracle lost alone leaves a mode still flying at 0.
TEST(Family, ALostRunsRevisitsCountAsWorst) {
  const std::vector<bool> repeated = {false, false, true, true, true};
  RunDigest oracle, lost;
  oracle.peak = {1.0, 1.0, 0.5, 0.5, 0.5};
  lost.peak = {1.0, 1.0, 0.5, 8e301, 0.0};
  lost.iae = std::nan("");
  const std::vector<RevisitRatio> q = revisitRatios(repeated, oracle, lost);
  ASSERT_EQ(q.size(), 3u);
  EXPECT_DOUBLE_EQ(q[0].ratio, 1.0);
  EXPECT_TRUE(std::isinf(q[1].ratio));
  EXPECT_TRUE(std::isinf(q[2].ratio));
  const std::vector<RevisitRatio> back = revisitRatios(repeated, lost, oracle);
  ASSERT_EQ(back.size(), 3u);
  EXPECT_DOUBLE_EQ(back[0].ratio, 1.0);
  EXPECT_EQ(back[1].ratio, 0.0);
  EXPECT_EQ(back[2].ratio, 0.0);
}

// A feasible regime: at the reference model's steady state, the trim deflection holds the
// plant still (alpha = r, q and alpha constant); the generator with the check keeps only regimes
// within the limit, counts the ones it threw away, and without it draws as before.
TEST(Family, FeasibleRegimesTrimWithinTheTravel) {
  const RunConfig cfg = readRunConfig([] {
    ParamValue tree = ParamValue::makeMap();
    tree.merge(loadYamlFile(defaultPlantPath()));
    tree.merge(loadYamlFile(defaultControllerPath()));
    tree.merge(loadYamlFile(scenarioPath("1")));
    return tree;
  }());
  ASSERT_TRUE(cfg.design.has_value());
  const auto& p = cfg.plant;
  const TrimCheck c = makeTrimCheck(p.A, p.B, p.B1r, cfg.design->K, 0.1, 0.175);
  const Eigen::Vector3d theta(2.0, 1.5, 3.0);
  const Eigen::VectorXd x = c.x_per_r * 0.1;
  const double u = c.trim(theta);
  const Eigen::VectorXd xdot = p.A * x + p.B * (theta.dot(x) + u) + p.B1r * 0.1;
  EXPECT_NEAR(xdot.norm(), 0.0, 1e-12) << xdot.transpose();
  EXPECT_NEAR(x[1], 0.1, 1e-12);  // alpha = r
  FamilySpec spec;
  int rejected = 0;
  for (int k = 0; k < 20; ++k) {
    const Scenario s = recurringScenario(spec, 21, k, &c, &rejected);
    for (size_t i = 1; i < s.theta.size(); ++i)
      EXPECT_LE(std::abs(c.trim(s.theta[i].theta)), 0.175 + 1e-15);
    EXPECT_EQ(scenarioToYaml(recurringScenario(spec, 21, k)),
              scenarioToYaml(recurringScenario(spec, 21, k, nullptr, nullptr)));
  }
  EXPECT_GT(rejected, 0);  // scales up to 10 need more than half the travel
  int none = 0;
  const TrimCheck all = makeTrimCheck(p.A, p.B, p.B1r, cfg.design->K, 0.1, 1e9);
  EXPECT_EQ(scenarioToYaml(recurringScenario(spec, 21, 3, &all, &none)),
            scenarioToYaml(recurringScenario(spec, 21, 3)));
  EXPECT_EQ(none, 0);
}

// Effort over a family's runs: medians and worst, the window fraction at a limit after the
// first window.
TEST(Family, EffortSummaryMediansAndWorst) {
  std::vector<RunDigest> runs(3);
  for (int k = 0; k < 3; ++k) {
    runs[static_cast<size_t>(k)].peak_applied = 0.1 * (k + 1);
    runs[static_cast<size_t>(k)].steady_tv = 0.01 * (3 - k);
    runs[static_cast<size_t>(k)].limit_frac = {0.9, 0.1 * k, 0.0};
  }
  const EffortSummary s = summarizeEffort(runs);
  EXPECT_DOUBLE_EQ(s.median_peak_u, 0.2);
  EXPECT_DOUBLE_EQ(s.worst_peak_u, 0.3);
  EXPECT_DOUBLE_EQ(s.median_tv, 0.02);
  EXPECT_DOUBLE_EQ(s.worst_window_limit, 0.2);  // the first window's 0.9 is not a switch
  EXPECT_DOUBLE_EQ(s.median_window_limit, 0.0);
}

#ifdef PMRAC_FAMILY_BIN
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <string>

namespace {
int runTool(const std::string& args, std::string* out) {
  FILE* p = popen((std::string(PMRAC_FAMILY_BIN) + " " + args + " 2>&1").c_str(), "r");
  char buf[4096];
  out->clear();
  while (fgets(buf, sizeof buf, p)) *out += buf;
  const int st = pclose(p);
  return WEXITSTATUS(st);
}
}  // namespace

// runs that leave the flight envelope are named in the summary (a line per run and
// the JSON's envelope_exits) and in runs.jsonl (envelope_exit); a family inside has neither.
TEST(FamilyTool, NamesTheRunsThatLeftTheEnvelope) {
  const std::string dir = "/tmp/pmrac_family_env_" + std::to_string(getpid());
  std::string out;
  ASSERT_EQ(runTool("--seed 3 --count 2 --modes rac --json --jobs 2 --out-dir " + dir +
                        " --set plant.envelope.max_alpha=0.05",
                    &out),
            0)
      << out;
  EXPECT_NE(out.find("\nrac             scenario 0 left the flight envelope at t = "),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("scenario 1 left the flight envelope"), std::string::npos) << out;
  EXPECT_NE(out.find("\"envelope_exits\":[{\"scenario\":0,"), std::string::npos) << out;
  std::ifstream runs(dir + "/runs.jsonl");
  std::string line;
  int n = 0;
  while (std::getline(runs, line)) {
    EXPECT_NE(line.find("\"envelope_exit\":{\"t\":"), std::string::npos) << line.substr(0, 200);
    EXPECT_NE(line.find("\"bound\":\"alpha\""), std::string::npos);
    ++n;
  }
  EXPECT_EQ(n, 2);
  ASSERT_EQ(runTool("--seed 3 --count 2 --modes rac --json --jobs 2", &out), 0) << out;
  EXPECT_EQ(out.find("envelope"), std::string::npos) << out;
  std::system(("rm -rf " + dir).c_str());
}

// --mismatch is deterministic, leaves every other value of the family as it was (M = 0
// is the family without the flag, byte for byte), and records each scenario's true A and B.
TEST(FamilyTool, MismatchIsDeterministicAndZeroIsTheFamily) {
  const std::string dir = "/tmp/pmrac_test_" + std::to_string(getpid()) + "_mismatch";
  const std::string common = "--seed 11 --count 2 --segments 6 --modes pa_robust --jobs 2 --json";
  // One --out-dir for every run (runs.jsonl names the scenario files by path).
  struct Family {
    std::string out, runs, scenario;
  };
  const auto family = [&](const std::string& flags) {
    Family f;
    EXPECT_EQ(runTool(common + flags + " --out-dir " + dir, &f.out), 0) << f.out;
    const auto read = [&](const std::string& name) {
      std::ifstream in(dir + "/" + name);
      return std::string(std::istreambuf_iterator<char>(in), {});
    };
    // Each run's wall time is measured, so it differs between two runs of the same family.
    f.runs = std::regex_replace(read("runs.jsonl"), std::regex("\"wall_time_s\":[^,}]*"),
                                "\"wall_time_s\":-");
    f.scenario = read("scenario_1.yaml");
    std::filesystem::remove_all(dir);
    return f;
  };
  const Family plain = family(""), zero = family(" --mismatch 0");
  const Family a = family(" --mismatch 0.5"), b = family(" --mismatch 0.5");
  EXPECT_EQ(plain.out, zero.out);
  EXPECT_TRUE(plain.runs == zero.runs);
  EXPECT_FALSE(plain.runs.empty());
  EXPECT_EQ(a.out, b.out);
  EXPECT_TRUE(a.runs == b.runs);
  EXPECT_NE(a.out, plain.out);
  EXPECT_NE(a.out.find("plant conditions: model mismatch 0.5 (per scenario)"), std::string::npos)
      << a.out;
  EXPECT_NE(a.out.find("drawn: mismatch factor in ["), std::string::npos) << a.out;
  EXPECT_NE(a.runs.find("\"drawn_conditions\":{\"plant.A\":[[0.0,1.0,0.0],[0.0,"),
            std::string::npos);
  EXPECT_NE(a.runs.find("\"plant.B\":[0.0,"), std::string::npos);
  EXPECT_NE(a.runs.find("\"mismatch_factors\":["), std::string::npos);
  // The draw moves no theta: the same scenario files.
  EXPECT_FALSE(a.scenario.empty());
  EXPECT_EQ(plain.scenario, a.scenario);
  std::string out;
  EXPECT_EQ(runTool("--seed 1 --count 1 --modes rac --mismatch 1", &out), 2);
  EXPECT_NE(out.find("--mismatch: expected M in [0, 1)"), std::string::npos) << out;
  EXPECT_EQ(runTool("--seed 1 --count 1 --modes rac --mismatch -0.1", &out), 2);
}

// runs.jsonl records the overrides every run was made with (--set, and a condition
// flag given as one value); it was empty whatever --set said.
TEST(FamilyTool, RunsRecordTheirOverrides) {
  const std::string dir = "/tmp/pmrac_test_" + std::to_string(getpid()) + "_overrides";
  std::string out;
  ASSERT_EQ(runTool("--seed 3 --count 1 --segments 6 --modes rac --jobs 1 --out-dir " + dir +
                        " --set controller.attention.c_e=0.006 --delay 0.01",
                    &out),
            0)
      << out;
  std::ifstream runs(dir + "/runs.jsonl");
  std::string line;
  ASSERT_TRUE(static_cast<bool>(std::getline(runs, line)));
  EXPECT_NE(line.find("\"overrides\":[\"controller.attention.c_e=0.006\","
                      "\"plant.actuator.delay=0.01\"]"),
            std::string::npos)
      << line.substr(0, 300);
  std::filesystem::remove_all(dir);
}

// --faults is refused, naming the flag, on the linear plant and for bad text.
TEST(FamilyTool, FaultsRefusedNamingTheFlag) {
  std::string out;
  const std::string jsb = " --set plant.engine=jsbsim";
  const std::pair<std::string, std::string> cases[] = {
      {"--faults cg_shift=0:0.05",
       "--faults: physical faults (CG shift, elevator effectiveness, "
       "pitch damping) need plant.engine jsbsim"},
      {"--faults cgshift=0:0.05" + jsb, "--faults: expected KEY=VALUE or KEY=LO:HI with KEY one"},
      {"--faults cg_shift" + jsb, "--faults: expected KEY=VALUE or KEY=LO:HI"},
      {"--faults cg_shift=0.5" + jsb,
       "--faults cg_shift: the CG shift [fraction of the chord, "
       "+ aft] must be in [-0.3, 0.3], got '0.5'"},
      {"--faults pitch_damping=0.5:3" + jsb, "--faults pitch_damping: both ends must be in [0, 2]"},
      {"--faults elevator_effectiveness=1:0.5" + jsb,
       "--faults elevator_effectiveness: a range LO:HI needs LO < HI"},
      {"--faults pitch_damping=x" + jsb, "--faults pitch_damping: expected a finite number"},
      {"--faults pitch_damping=1,pitch_damping=0.5" + jsb, "--faults: pitch_damping given twice"},
  };
  for (const auto& c : cases) {
    EXPECT_EQ(runTool("--seed 1 --count 1 --modes rac " + c.first, &out), 2) << c.first;
    EXPECT_NE(out.find(c.second), std::string::npos) << c.first << "\n" << out;
  }
}

// Every family flies the aircraft's elevator by default (config/plant/elevator_b747.yaml), draws
// regimes it can trim and says how many it rejected, and reports the effort beside the ratios;
// --elevator ideal is the plant file's unlimited elevator, every regime kept.
TEST(FamilyTool, AircraftElevatorByDefaultWithEffortAndRejections) {
  const std::string dir = "/tmp/pmrac_test_" + std::to_string(getpid()) + "_elevator";
  std::string out;
  ASSERT_EQ(
      runTool("--seed 5 --count 2 --segments 6 --modes rac --json --jobs 1 --out-dir " + dir, &out),
      0)
      << out;
  EXPECT_NE(out.find("\nelevator: b747, travel 0.35 rad, rate 0.65 rad/s; feasible regimes (trim "
                     "within 0.5 of the travel at |r| 0.1): "),
            std::string::npos)
      << out;
  EXPECT_NE(out.find(" || "), std::string::npos) << out;
  EXPECT_NE(out.find("\"effort\":{\"median_peak_abs_u\":"), std::string::npos) << out;
  EXPECT_NE(out.find("\"rejected_regimes\":"), std::string::npos) << out;
  std::ifstream runs(dir + "/runs.jsonl");
  std::string line;
  int n = 0;
  while (std::getline(runs, line)) {
    const std::string key = "\"effort\":{\"peak_abs_u\":";
    const size_t at = line.find(key);
    ASSERT_NE(at, std::string::npos) << line.substr(0, 200);
    EXPECT_LE(std::stod(line.substr(at + key.size())), 0.35 + 1e-12);
    EXPECT_NE(line.find("\"window_time_at_limit\":["), std::string::npos);
    ++n;
  }
  EXPECT_EQ(n, 2);
  std::filesystem::remove_all(dir);
  ASSERT_EQ(
      runTool("--seed 5 --count 2 --segments 6 --modes rac --json --jobs 1 --elevator ideal", &out),
      0)
      << out;
  EXPECT_NE(out.find("\nelevator: ideal, no travel or rate limit"), std::string::npos) << out;
  EXPECT_EQ(out.find("rejected"), std::string::npos) << out;
  EXPECT_EQ(runTool("--seed 1 --count 1 --modes rac --elevator /nonexistent.yaml", &out), 2);
  EXPECT_NE(out.find("--elevator: expected b747, ideal or the path"), std::string::npos) << out;
  EXPECT_EQ(runTool("--seed 1 --count 1 --modes rac --trim-fraction 0", &out), 2);
  EXPECT_NE(out.find("--trim-fraction: expected a fraction in (0, 1]"), std::string::npos) << out;
}

// With the oracle, each mode's revisits against it in the table, the JSON and runs.jsonl (the
// oracle's own all at 1); without it "-" and null.
TEST(FamilyTool, RevisitsAgainstTheOracleOrDash) {
  const std::string dir = "/tmp/pmrac_test_" + std::to_string(getpid()) + "_revisits";
  std::string out;
  ASSERT_EQ(
      runTool("--seed 5 --count 2 --segments 6 --modes oracle --json --jobs 1 --out-dir " + dir,
              &out),
      0)
      << out;
  EXPECT_NE(out.find(" u/oracle | rev:n rev:med rev:wst rev<=1.2 || "), std::string::npos) << out;
  const std::smatch header = [&] {
    std::smatch m;
    std::regex_search(out, m, std::regex("; (\\d+) repeated-switch windows"));
    return m;
  }();
  ASSERT_FALSE(header.empty()) << out;
  const std::string count = header[1];
  EXPECT_NE(out.find("\"mode\":\"oracle\""), std::string::npos) << out;
  EXPECT_NE(out.find("\"revisits\":{\"count\":" + count +
                     ",\"median\":1.0,\"worst\":1.0,\"within_1_2\":1.0}"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("\"revisits\":{\"count\":" + count + ",\"median\":"), std::string::npos)
      << out;  // rac's
  std::ifstream runs(dir + "/runs.jsonl");
  std::string line;
  int n = 0;
  while (std::getline(runs, line)) {
    EXPECT_NE(line.find("\"revisits\":{\"windows\":["), std::string::npos) << line.substr(0, 200);
    EXPECT_NE(line.find("\"ratio_to_oracle\":["), std::string::npos) << line.substr(0, 200);
    ++n;
  }
  EXPECT_EQ(n, 4);  // rac and the oracle on 2 scenarios
  std::filesystem::remove_all(dir);
  ASSERT_EQ(
      runTool("--seed 5 --count 2 --segments 6 --modes rac --json --jobs 1 --out-dir " + dir, &out),
      0)
      << out;
  EXPECT_NE(out.find("|     -       -       -        - || "), std::string::npos) << out;
  EXPECT_NE(out.find("\"revisits\":null"), std::string::npos) << out;
  runs = std::ifstream(dir + "/runs.jsonl");
  ASSERT_TRUE(static_cast<bool>(std::getline(runs, line)));
  EXPECT_NE(line.find("\"ratio_to_oracle\":null"), std::string::npos) << line.substr(0, 200);
  std::filesystem::remove_all(dir);
}

TEST(FamilyTool, ReportsEveryModeAndRefusesBadInput) {
  std::string out;
  ASSERT_EQ(runTool("--seed 3 --count 2 --modes pa_robust,oracle --json --jobs 2", &out), 0) << out;
  // rac is added as the yardstick; every mode gets a table row and a JSON line.
  for (const char* m : {"\nrac ", "\npa_robust ", "\noracle ", "\"mode\":\"pa_robust\""})
    EXPECT_NE(out.find(m), std::string::npos) << m << "\n" << out;
  EXPECT_EQ(runTool("--count 2", &out), 2);
  EXPECT_NE(out.find("--seed is required"), std::string::npos) << out;
  EXPECT_EQ(runTool("--seed 1 --modes rac,nope", &out), 2);
  EXPECT_NE(out.find("unknown mode 'nope'"), std::string::npos) << out;
  EXPECT_EQ(runTool("--seed 1 --set controller.robust.margin=2", &out), 2);
  EXPECT_NE(out.find("controller.robust.margin"), std::string::npos) << out;
  EXPECT_EQ(runTool("--seed 1 --scales -1:2", &out), 2);
  EXPECT_NE(out.find("--scales: both ends must be of one sign"), std::string::npos) << out;
  EXPECT_EQ(runTool("--seed 1 --reference -0.01:0.01", &out), 2);
  EXPECT_NE(out.find("--reference: needs --ref-every"), std::string::npos) << out;
}

// Negative scales and a command about zero: the scenarios written carry them.
TEST(FamilyTool, ScalesAndReferenceShapeTheScenarios) {
  const std::string dir = ::testing::TempDir() + "family_scales";
  std::filesystem::remove_all(dir);
  std::string out;
  ASSERT_EQ(runTool("--seed 5 --count 1 --regimes 2 --segments 4 --modes rac --jobs 1 --scales "
                    "-0.6:-0.15 --ref-every 2 --reference -0.01:0.01 --out-dir " +
                        dir,
                    &out),
            0)
      << out;
  const ParamValue tree = loadYamlFile(dir + "/scenario_0.yaml");
  ParamReader reader(tree);
  const Scenario s = Scenario::read(reader, 3, "scenario");
  ASSERT_TRUE(reader.ok()) << ConfigError(reader.problems()).what();
  for (size_t i = 1; i < s.theta.size(); ++i) EXPECT_LT(s.theta[i].theta.maxCoeff(), 0.0);
  EXPECT_EQ(s.reference.front().r, 0.0);  // (LO + HI) / 2 first
  for (const auto& seg : s.reference) {
    EXPECT_GE(seg.r, -0.01);
    EXPECT_LE(seg.r, 0.01);
  }
  EXPECT_GT(s.reference.size(), 20u);
  std::filesystem::remove_all(dir);
}

// --count, --regimes, --segments and --jobs are counts: a whole number from 1 to the flag's
// limit. A number past the int range is refused, not wrapped (4294967297 regimes is not 1).
TEST(FamilyTool, ParsesCountsAsCounts) {
  std::string out;
  const std::pair<std::string, std::string> cases[] = {
      {"--count 0", "--count: expected a whole number in 1..100000, got '0'"},
      {"--count=-3", "--count: expected a whole number in 1..100000, got '-3'"},
      {"--count 2x", "--count: expected a whole number in 1..100000, got '2x'"},
      {"--count 1 --regimes 4294967297",
       "--regimes: expected a whole number in 1..50, got '4294967297'"},
      {"--count 1 --segments 4294967306",
       "--segments: expected a whole number in 1..1000, got '4294967306'"},
      {"--count 1 --jobs 0", "--jobs: expected a whole number in 1..1024, got '0'"},
      {"--count 1 --jobs 18446744073709551617",
       "--jobs: expected a whole number in 1..1024, got '18446744073709551617'"},
  };
  for (const auto& c : cases) {
    EXPECT_EQ(runTool("--seed 1 --modes rac " + c.first, &out), 2) << c.first << "\n" << out;
    EXPECT_NE(out.find(c.second), std::string::npos) << c.first << "\n" << out;
  }
  EXPECT_EQ(runTool("--seed 1 --modes rac --count 01 --regimes 2 --segments 4 --jobs 1", &out), 0)
      << out;
  EXPECT_NE(out.find("1 scenarios, 2 regimes, 4 segments"), std::string::npos) << out;
}
#endif

// the true plant of --mismatch M: the alpha and q rows of A and B scaled per entry by
// factors in [1 - M, 1 + M], deterministic per (seed, scenario), M = 0 the nominal plant.
TEST(Family, MismatchedPlantDrawsFactorsInRangeDeterministically) {
  Eigen::MatrixXd A(3, 3);
  A << 0.0, 1.0, 0.0, 0.0, -0.32, 0.86, 0.0, -0.93, -0.43;
  Eigen::VectorXd B(3);
  B << 0.0, -0.02, -1.16;
  double lo = 2.0, hi = 0.0;
  for (int k = 0; k < 100; ++k) {
    const PlantMismatch m = mismatchedPlant(A, B, 0.3, 4711, k);
    ASSERT_EQ(m.factors.size(), 8u);  // A(1, 0..2), A(2, 0..2), B(1), B(2)
    for (const double f : m.factors) {
      EXPECT_GE(f, 0.7);
      EXPECT_LE(f, 1.3);
      lo = std::min(lo, f);
      hi = std::max(hi, f);
    }
    EXPECT_EQ(m.A.row(0), A.row(0));  // the integrator row is kinematics: unchanged
    EXPECT_EQ(m.B[0], B[0]);
    for (int j = 0; j < 3; ++j) {
      EXPECT_EQ(m.A(1, j), A(1, j) * m.factors[static_cast<size_t>(j)]);
      EXPECT_EQ(m.A(2, j), A(2, j) * m.factors[static_cast<size_t>(3 + j)]);
    }
    EXPECT_EQ(m.B[1], B[1] * m.factors[6]);
    EXPECT_EQ(m.B[2], B[2] * m.factors[7]);
    const PlantMismatch again = mismatchedPlant(A, B, 0.3, 4711, k);
    EXPECT_EQ(again.A, m.A);
    EXPECT_EQ(again.B, m.B);
    const PlantMismatch none = mismatchedPlant(A, B, 0.0, 4711, k);
    EXPECT_EQ(none.A, A);
    EXPECT_EQ(none.B, B);
  }
  EXPECT_LT(lo, 0.72);  // spread over the range
  EXPECT_GT(hi, 1.28);
  EXPECT_NE(mismatchedPlant(A, B, 0.3, 4711, 0).A, mismatchedPlant(A, B, 0.3, 4711, 1).A);
  EXPECT_NE(mismatchedPlant(A, B, 0.3, 4711, 0).A, mismatchedPlant(A, B, 0.3, 4712, 0).A);
  EXPECT_THROW(mismatchedPlant(A, B, 1.0, 1, 0), std::invalid_argument);
  EXPECT_THROW(mismatchedPlant(A.topLeftCorner(2, 2), B.head(2), 0.1, 1, 0), std::invalid_argument);
}

TEST(Family, ALostRunCountsAsWorstNotBetter) {
  // A run that diverges in window 1: its later windows hold peak 0 (|e| NaN compares false) and
  // its IAE is NaN. They are the worst windows of the family, not halved ones.
  const std::vector<std::vector<bool>> repeated = {{false, false, true, true}};
  const std::vector<RunDigest> rac = {{{1, 1, 1, 1}, 10.0, 1.0}};
  const std::vector<RunDigest> mode = {{{0.5, 8e301, 0.0, 0.0}, std::nan(""), std::nan("")}};
  const FamilySummary s = summarizeFamily(repeated, rac, mode, &rac);
  EXPECT_EQ(s.lost_runs, 1);
  EXPECT_EQ(s.windows, 2);
  EXPECT_EQ(s.frac_better, 0.0);
  EXPECT_EQ(s.frac_halved, 0.0);
  EXPECT_TRUE(std::isinf(s.worst_ratio));
  EXPECT_TRUE(std::isinf(s.median_ratio));
  EXPECT_TRUE(std::isinf(s.worst_iae_ratio));
  EXPECT_EQ(s.iae_over, 1);
  EXPECT_TRUE(std::isinf(s.worst_u_oracle));
}

// --out-dir keeps an earlier family: a second run into the same folder is refused, naming the
// flag and the file, and leaves runs.jsonl as it was; with --force it replaces them.
TEST(FamilyTool, OutDirKeepsAnEarlierFamilyWithoutForce) {
  const std::string dir = "/tmp/pmrac_family_keep_" + std::to_string(getpid());
  const std::string run = "--count 1 --segments 6 --modes rac --jobs 1 --out-dir " + dir;
  std::string out;
  ASSERT_EQ(runTool("--seed 3 " + run, &out), 0) << out;
  const auto read = [&]() {
    std::ifstream in(dir + "/runs.jsonl");
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string first = read();
  ASSERT_FALSE(first.empty());
  EXPECT_EQ(runTool("--seed 4 " + run, &out), 2) << out;
  EXPECT_NE(out.find("--out-dir: '" + dir + "' holds an earlier family (runs.jsonl)"),
            std::string::npos)
      << out;
  EXPECT_EQ(read(), first);
  EXPECT_EQ(runTool("--seed 4 --force " + run, &out), 0) << out;
  EXPECT_NE(read(), first);
  std::filesystem::remove_all(dir);
}
