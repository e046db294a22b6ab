#include "preadaptive_mrac/core/sim/scenario_family.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace preadaptive_mrac {

namespace {
// Portable uniform numbers: mt19937_64's sequence is fixed by the standard, the mapping is ours.
class Uniform {
 public:
  explicit Uniform(std::uint64_t seed) : gen_(seed) {}
  double next() { return static_cast<double>(gen_() >> 11) * (1.0 / 9007199254740992.0); }
  double in(double a, double b) { return a + (b - a) * next(); }
  int below(int n) { return std::min(n - 1, static_cast<int>(next() * n)); }

 private:
  std::mt19937_64 gen_;
};

std::uint64_t mix(std::uint64_t seed, std::uint64_t index) {
  // splitmix64 of the pair, so neighbouring seeds and indices give unrelated streams.
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL + index + 0x632BE59BD9B4E019ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}
}  // namespace

Scenario recurringScenario(const FamilySpec& spec, std::uint64_t seed, int index,
                           const TrimCheck* feasible, int* rejected) {
  if (spec.regimes < 1 || spec.segments < 2 * spec.regimes || spec.n < 1)
    throw std::invalid_argument("family: need regimes >= 1 and segments >= 2 * regimes");
  Uniform u(mix(seed, static_cast<std::uint64_t>(index)));
  std::vector<Eigen::VectorXd> regimes;
  for (int k = 0; k < spec.regimes; ++k) {
    Eigen::VectorXd th(spec.n);
    for (int attempt = 0;; ++attempt) {
      if (attempt == 1000)
        throw std::runtime_error(
            "family: 1000 regimes in a row need more elevator to trim than the limit allows "
            "(lower the scales or raise plant.actuator.max_deflection)");
      // Negative scales: |s| log-uniform between |max_scale| and |min_scale|.
      const double s = spec.min_scale > 0.0
                           ? std::exp(u.in(std::log(spec.min_scale), std::log(spec.max_scale)))
                           : -std::exp(u.in(std::log(-spec.max_scale), std::log(-spec.min_scale)));
      for (int i = 0; i < spec.n; ++i) th[i] = s * (1.0 + spec.spread * u.in(-1.0, 1.0));
      if (feasible == nullptr || feasible->holds(th)) break;
      if (rejected) ++*rejected;
    }
    regimes.push_back(th);
  }
  // Visit order: every regime twice, the rest at random, no regime twice in a row.
  std::vector<int> order;
  for (int attempt = 0; attempt < 1000 && order.empty(); ++attempt) {
    std::vector<int> pool;
    for (int k = 0; k < spec.regimes; ++k) pool.insert(pool.end(), {k, k});
    while (static_cast<int>(pool.size()) < spec.segments) pool.push_back(u.below(spec.regimes));
    for (int i = static_cast<int>(pool.size()) - 1; i > 0; --i)
      std::swap(pool[static_cast<size_t>(i)], pool[static_cast<size_t>(u.below(i + 1))]);
    bool ok = true;
    for (size_t i = 1; i < pool.size(); ++i) ok = ok && pool[i] != pool[i - 1];
    if (ok) order = pool;
  }
  if (order.empty()) {  // one regime, or an unlucky draw: alternate deterministically
    for (int i = 0; i < spec.segments; ++i) order.push_back(i % spec.regimes);
  }
  Scenario sc;
  sc.name = "family_" + std::to_string(seed) + "_" + std::to_string(index);
  sc.description = "recurring regimes, seed " + std::to_string(seed) + ", scenario " +
                   std::to_string(index) + " (preadapt_family)";
  double t = spec.first_duration;
  sc.theta.push_back({t, Eigen::VectorXd::Constant(spec.n, spec.first_scale)});
  for (int k : order) {
    t += u.in(spec.min_duration, spec.max_duration);
    t = std::round(t * 1000.0) / 1000.0;  // whole milliseconds: switches fall on samples
    sc.theta.push_back({t, regimes[static_cast<size_t>(k)]});
  }
  if (spec.ref_every > 0.0) {
    double tr = 0.0;
    double r = spec.r;
    while (true) {
      const double next = std::round((tr + u.in(0.5, 1.5) * spec.ref_every) * 1000.0) / 1000.0;
      if (next >= t) break;
      sc.reference.push_back({next, r});
      r = u.in(spec.r_min, spec.r_max);
      tr = next;
    }
    sc.reference.push_back({t, r});
  } else {
    sc.reference.push_back({t, spec.r});
  }
  return sc;
}

double drawCondition(const ConditionRange& range, std::uint64_t seed, int index,
                     std::uint64_t stream) {
  if (!range.drawn()) return range.lo;
  // A stream of its own, apart from the scenario's theta draws (mix(seed, index)).
  Uniform u(mix(mix(seed, static_cast<std::uint64_t>(index)), stream + 1));
  return u.in(range.lo, range.hi);
}

PlantMismatch mismatchedPlant(const Eigen::MatrixXd& A, const Eigen::VectorXd& B, double M,
                              std::uint64_t seed, int index) {
  if (A.rows() < 3 || A.cols() != A.rows() || B.size() != A.rows())
    throw std::invalid_argument("mismatch: needs the plant's x = [e_I, alpha, q] (n >= 3)");
  if (!(M >= 0.0 && M < 1.0)) throw std::invalid_argument("mismatch: M must be in [0, 1)");
  PlantMismatch out{A, B, {}};
  // Stream 2001: apart from the theta draws (mix(seed, index)), the conditions (1, 2, 3) and
  // the Lambdas (1000 + k).
  Uniform u(mix(mix(seed, static_cast<std::uint64_t>(index)), 2001));
  const auto factor = [&] {
    out.factors.push_back(u.in(1.0 - M, 1.0 + M));
    return out.factors.back();
  };
  for (Eigen::Index i = 1; i <= 2; ++i)
    for (Eigen::Index j = 0; j < A.cols(); ++j) out.A(i, j) *= factor();
  for (Eigen::Index i = 1; i <= 2; ++i) out.B[i] *= factor();
  return out;
}

namespace {
// Per theta segment, the order in which its regime (its theta) first appeared after the first
// segment (0, 1, ...), or -1 for the first segment and any segment with its theta.
std::vector<int> regimeOrdinals(const Scenario& s) {
  std::vector<int> out;
  std::vector<std::pair<Eigen::VectorXd, int>> seen;
  int draws = 0;
  for (size_t i = 0; i < s.theta.size(); ++i) {
    const Eigen::VectorXd& th = s.theta[i].theta;
    int ordinal = -1;
    bool found = false;
    for (const auto& kv : seen)
      if (kv.first == th) {
        ordinal = kv.second;
        found = true;
      }
    if (!found) {
      if (i > 0) ordinal = draws++;
      seen.emplace_back(th, ordinal);
    }
    out.push_back(ordinal);
  }
  return out;
}
}  // namespace

std::vector<Scenario::EffectivenessSegment> regimeEffectiveness(const Scenario& s,
                                                                const ConditionRange& range,
                                                                std::uint64_t seed, int index) {
  std::vector<Scenario::EffectivenessSegment> out;
  const std::vector<int> regime = regimeOrdinals(s);
  for (size_t i = 0; i < s.theta.size(); ++i) {
    // The first segment: the trim before any regime.
    const double lambda =
        regime[i] < 0
            ? 1.0
            : drawCondition(range, seed, index, 1000 + static_cast<std::uint64_t>(regime[i]));
    out.push_back({s.theta[i].until, lambda});
  }
  return out;
}

FaultRanges::FaultRanges() {
  const Scenario::FaultSegment nominal{};
  for (size_t j = 0; j < range.size(); ++j) {
    const double v = nominal.*Scenario::kFaultKeys[j].field;
    range[j] = {v, v};
  }
}

std::vector<Scenario::FaultSegment> regimeFaults(const Scenario& s, const FaultRanges& ranges,
                                                 std::uint64_t seed, int index) {
  std::vector<Scenario::FaultSegment> out;
  const std::vector<int> regime = regimeOrdinals(s);
  for (size_t i = 0; i < s.theta.size(); ++i) {
    Scenario::FaultSegment seg{};
    seg.until = s.theta[i].until;
    if (regime[i] >= 0)  // the first segment: the nominal aircraft it was trimmed as
      for (size_t j = 0; j < ranges.range.size(); ++j)
        seg.*Scenario::kFaultKeys[j].field = drawCondition(
            ranges.range[j], seed, index, 3000 + 3 * static_cast<std::uint64_t>(regime[i]) + j);
    out.push_back(seg);
  }
  return out;
}

std::vector<bool> repeatedWindows(const Scenario& s) {
  std::vector<bool> out(s.theta.size(), false);
  for (size_t i = 1; i < s.theta.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (s.theta[j].theta.size() == s.theta[i].theta.size() &&
          s.theta[j].theta == s.theta[i].theta)
        out[i] = true;
  return out;
}

namespace {
double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}
double ratio(double a, double b) { return b > 0.0 ? a / b : (a > 0.0 ? INFINITY : 1.0); }

// The window a lost run (IAE not finite) blew up in: its windows after it hold peaks of 0 (|e|
// NaN compares false), so the blow-up is the last window whose peak is NaN or a new largest.
// A run that was not lost: the number of its windows (no window is lost).
size_t blowUpWindow(const RunDigest& run) {
  size_t blow_up = run.peak.size();
  if (std::isfinite(run.iae)) return blow_up;
  double top = -1.0;
  for (size_t w = 0; w < run.peak.size(); ++w)
    if (!(run.peak[w] <= top)) {  // NaN or larger
      top = std::isfinite(run.peak[w]) ? run.peak[w] : HUGE_VAL;
      blow_up = w;
    }
  return blow_up;
}
}  // namespace

double TrimCheck::trim(const Eigen::VectorXd& theta) const {
  return r_max * (v_per_r - theta.dot(x_per_r));
}

TrimCheck makeTrimCheck(const Eigen::MatrixXd& A, const Eigen::VectorXd& B,
                        const Eigen::VectorXd& B1r, const Eigen::RowVectorXd& K, double r_max,
                        double limit) {
  const Eigen::MatrixXd Am = A - B * K;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(Am);
  if (!lu.isInvertible())
    throw std::invalid_argument("trim check: the reference model A - B K is singular");
  TrimCheck c;
  c.x_per_r = -lu.solve(B1r);
  c.v_per_r = -(K * c.x_per_r)(0);
  c.r_max = std::abs(r_max);
  c.limit = limit;
  return c;
}

EffortSummary summarizeEffort(const std::vector<RunDigest>& runs) {
  EffortSummary s;
  std::vector<double> peak, travel, rate, tv, win;
  for (const auto& r : runs) {
    peak.push_back(r.peak_applied);
    travel.push_back(r.time_at_travel);
    rate.push_back(r.time_at_rate);
    tv.push_back(r.steady_tv);
    for (size_t w = 1; w < r.limit_frac.size(); ++w) win.push_back(r.limit_frac[w]);
  }
  const auto worst = [](const std::vector<double>& v) {
    return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
  };
  s.median_peak_u = median(peak);
  s.worst_peak_u = worst(peak);
  s.median_travel = median(travel);
  s.worst_travel = worst(travel);
  s.median_rate = median(rate);
  s.worst_rate = worst(rate);
  s.median_tv = median(tv);
  s.worst_tv = worst(tv);
  s.median_window_limit = median(win);
  s.worst_window_limit = worst(win);
  return s;
}

double noisePeak(double sigma, double samples) {
  return samples >= 1.0 ? sigma * std::sqrt(2.0 * std::log(2.0 * samples)) : sigma;
}

std::vector<bool> quietWindows(const Scenario& s, double dt, double sigma, const RunDigest& rac,
                               double factor) {
  std::vector<bool> out(rac.peak.size(), false);
  if (!(sigma > 0.0 && factor > 0.0 && dt > 0.0)) return out;
  const std::vector<double> switches = s.switchTimes();
  double start = 0.0;
  for (size_t w = 0; w < out.size(); ++w) {
    const double end = w < switches.size() ? switches[w] : s.endTime();
    // A lost run's windows after its blow-up hold inf or NaN: never quiet.
    out[w] = w > 0 && rac.peak[w] <= factor * noisePeak(sigma, (end - start) / dt);
    start = end;
  }
  return out;
}

namespace {
bool isQuiet(const std::vector<std::vector<bool>>* quiet, size_t k, size_t w) {
  return quiet && k < quiet->size() && w < (*quiet)[k].size() && (*quiet)[k][w];
}
}  // namespace

FamilySummary summarizeFamily(const std::vector<std::vector<bool>>& repeated,
                              const std::vector<RunDigest>& rac, const std::vector<RunDigest>& mode,
                              const std::vector<RunDigest>* oracle,
                              const std::vector<std::vector<bool>>* quiet) {
  FamilySummary s;
  std::vector<double> all;
  int better = 0, halved = 0;
  for (size_t k = 0; k < mode.size() && k < rac.size() && k < repeated.size(); ++k) {
    // A run lost to divergence (IAE not finite): its windows after the blow-up hold peaks of 0
    // (|e| NaN compares false), which must count as the worst, not as better than rac.
    const bool lost = !std::isfinite(mode[k].iae);
    const size_t blow_up = blowUpWindow(mode[k]);
    s.lost_runs += lost;
    for (size_t w = 1; w < mode[k].peak.size() && w < rac[k].peak.size(); ++w) {
      const bool rep = w < repeated[k].size() && repeated[k][w];
      if (isQuiet(quiet, k, w) && w < blow_up) {  // a run lost there counts, quiet or not
        s.quiet += rep;
        continue;
      }
      const double q = w >= blow_up ? HUGE_VAL : ratio(mode[k].peak[w], rac[k].peak[w]);
      all.push_back(q);
      if (rep) {
        s.ratios.push_back(q);
        better += q < 1.0;
        halved += q <= 0.5;
      }
    }
    const double qi = lost ? HUGE_VAL : ratio(mode[k].iae, rac[k].iae);
    s.worst_iae_ratio = std::max(s.worst_iae_ratio, qi);
    s.iae_over += qi > 1.05;
    s.worst_u_rac =
        std::max(s.worst_u_rac, lost ? HUGE_VAL : ratio(mode[k].max_abs_u, rac[k].max_abs_u));
    if (oracle && k < oracle->size())
      s.worst_u_oracle = std::max(
          s.worst_u_oracle, lost ? HUGE_VAL : ratio(mode[k].max_abs_u, (*oracle)[k].max_abs_u));
  }
  s.windows = static_cast<int>(s.ratios.size());
  if (s.windows > 0) {
    s.frac_better = static_cast<double>(better) / s.windows;
    s.frac_halved = static_cast<double>(halved) / s.windows;
    s.median_ratio = median(s.ratios);
    s.worst_ratio = *std::max_element(s.ratios.begin(), s.ratios.end());
  }
  if (!all.empty()) {
    s.all_median_ratio = median(all);
    s.all_worst_ratio = *std::max_element(all.begin(), all.end());
  }
  return s;
}

std::vector<RevisitRatio> revisitRatios(const std::vector<bool>& repeated, const RunDigest& oracle,
                                        const RunDigest& mode, const std::vector<bool>* quiet) {
  std::vector<RevisitRatio> out;
  const size_t mode_lost = blowUpWindow(mode), oracle_lost = blowUpWindow(oracle);
  for (size_t w = 1; w < repeated.size() && w < mode.peak.size() && w < oracle.peak.size(); ++w) {
    if (!repeated[w] || (quiet && w < quiet->size() && (*quiet)[w] && w < mode_lost)) continue;
    const double q = w >= mode_lost     ? HUGE_VAL
                     : w >= oracle_lost ? 0.0
                                        : ratio(mode.peak[w], oracle.peak[w]);
    out.push_back({static_cast<int>(w), q});
  }
  return out;
}

RevisitSummary summarizeRevisits(const std::vector<std::vector<bool>>& repeated,
                                 const std::vector<RunDigest>& oracle,
                                 const std::vector<RunDigest>& mode,
                                 const std::vector<std::vector<bool>>* quiet) {
  RevisitSummary s;
  int within = 0;
  for (size_t k = 0; k < repeated.size() && k < oracle.size() && k < mode.size(); ++k)
    for (const RevisitRatio& r :
         revisitRatios(repeated[k], oracle[k], mode[k],
                       quiet && k < quiet->size() ? &(*quiet)[k] : nullptr)) {
      s.ratios.push_back(r.ratio);
      within += r.ratio <= kRevisitTolerance;
    }
  s.count = static_cast<int>(s.ratios.size());
  if (s.count > 0) {
    s.median = median(s.ratios);
    s.worst = *std::max_element(s.ratios.begin(), s.ratios.end());
    s.within = static_cast<double>(within) / s.count;
  }
  return s;
}

}  // namespace preadaptive_mrac
