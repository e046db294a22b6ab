#pragma once
/// \file scenario_family.hpp
/// \brief Random recurring-regime scenarios from a seed (docs/spec.md "Beyond the paper"): after a
/// first segment at theta = 0.1 ones, the plant switches between a few fixed regimes, each
/// visited at least twice. How a mode is judged against rac on such a family: family_report.

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "preadaptive_mrac/core/sim/scenario.hpp"

namespace preadaptive_mrac {

/// \brief Shape of a family.
struct FamilySpec {
  int n = 3;                    ///< state dimension (theta has n components)
  int regimes = 3;              ///< distinct regimes
  int segments = 10;            ///< segments after the first (>= 2 * regimes)
  double first_duration = 5.0;  ///< the first segment at theta = first_scale ones [s]
  double first_scale = 0.1;
  double min_duration = 10.0, max_duration = 20.0;  ///< segment lengths [s], uniform
  /// Regime scale s, log-uniform in [min, max]; both negative: |s| log-uniform in [-max, -min].
  double min_scale = 0.5, max_scale = 10.0;
  double spread = 0.5;  ///< components s * (1 + spread * U[-1, 1]), so they differ
  double r = 0.1;       ///< reference [rad]
  /// Reference steps: when > 0, r takes a new value in [r_min, r_max] every so many seconds
  /// (uniform in [ref_every / 2, 3 ref_every / 2]).
  double ref_every = 0.0;
  double r_min = 0.05, r_max = 0.15;
};

struct TrimCheck;

/// \brief Scenario `index` of the family `seed` (deterministic on every platform). With
/// `feasible`, a drawn regime that the limited elevator cannot hold is drawn again from the
/// same stream (at most 1000 times, then std::runtime_error), and `rejected` (when given) counts
/// the draws thrown away; without it the draws are as they always were.
Scenario recurringScenario(const FamilySpec& spec, std::uint64_t seed, int index,
                           const TrimCheck* feasible = nullptr, int* rejected = nullptr);

/// \brief A plant condition drawn per scenario of a family: uniform in [lo, hi]; lo == hi is
/// that one value, drawn by no one.
struct ConditionRange {
  double lo = 0.0, hi = 0.0;
  bool drawn() const { return hi > lo; }
};

/// \brief The value of `range` for scenario `index` of family `seed` (deterministic on every
/// platform); `stream` keeps the draws of different conditions apart.
double drawCondition(const ConditionRange& range, std::uint64_t seed, int index,
                     std::uint64_t stream);

/// \brief An effectiveness schedule for `s` with one Lambda per distinct theta (regime), uniform
/// in `range`, the first segment's 1: a regime revisited brings its own Lambda back.
std::vector<Scenario::EffectivenessSegment> regimeEffectiveness(const Scenario& s,
                                                                const ConditionRange& range,
                                                                std::uint64_t seed, int index);

/// \brief Physical faults drawn per regime (`preadapt_family --faults`, JSBSim only): one range
/// per key of Scenario::kFaultKeys, in that order; a range with lo == hi is that value in every
/// regime. Default: every key nominal (cg_shift 0, the multipliers 1).
struct FaultRanges {
  FaultRanges();
  std::array<ConditionRange, 3> range;
};

/// \brief A fault schedule for `s` with one set of faults per regime (distinct theta), each key
/// uniform in its range, the first segment the nominal aircraft: a regime revisited brings its
/// faults back. Key j of the regime drawn r-th (r = 0, 1, ...) comes from stream 3000 + 3 r + j
/// of drawCondition (apart from the theta draws, the conditions, the Lambdas and the mismatch).
std::vector<Scenario::FaultSegment> regimeFaults(const Scenario& s, const FaultRanges& ranges,
                                                 std::uint64_t seed, int index);

/// \brief A true plant that differs from the controller's model (`preadapt_family --mismatch M`).
struct PlantMismatch {
  Eigen::MatrixXd A;            ///< the true A
  Eigen::VectorXd B;            ///< the true B
  std::vector<double> factors;  ///< the factors in the order drawn (A's rows, then B's entries)
};

/// \brief Scenario `index`'s true plant of family `seed`: every entry of the alpha and q rows of
/// A (rows 1 and 2 of x = [e_I, alpha, q], all n columns: the aerodynamic derivatives Z/mU and
/// M/Iy; zeros stay zero) and of B (entries 1 and 2) each scaled by its own factor, uniform in
/// [1 - M, 1 + M], drawn in the order A(1,0..n-1), A(2,0..n-1), B(1), B(2) from a stream of
/// its own (apart from the theta draws and the conditions' streams, so the rest of the family
/// is unchanged). M = 0 gives factors 1 (A and B unchanged). Needs n >= 3 and 0 <= M < 1.
PlantMismatch mismatchedPlant(const Eigen::MatrixXd& A, const Eigen::VectorXd& B, double M,
                              std::uint64_t seed, int index);

/// \brief Windows (0 = the first segment) whose theta equals that of an earlier segment.
std::vector<bool> repeatedWindows(const Scenario& s);

/// \brief What the family report needs of one run.
struct RunDigest {
  std::vector<double> peak;  ///< peak |e| per window [rad]
  double iae = 0.0;          ///< whole run [rad s]
  double max_abs_u = 0.0;    ///< [rad]
  // Effort (closed_loop.hpp EffortMetrics): of the applied elevator.
  double peak_applied = 0.0;       ///< max |applied| [rad]
  double time_at_travel = 0.0;     ///< [s]
  double time_at_rate = 0.0;       ///< [s]
  double steady_tv = 0.0;          ///< [rad]
  std::vector<double> limit_frac;  ///< per window: fraction of its time at a limit
};

/// \brief The elevator effort of one mode over a family: medians and worst over its runs.
struct EffortSummary {
  double median_peak_u = 0.0, worst_peak_u = 0.0;  ///< max |applied| [rad]
  double median_travel = 0.0, worst_travel = 0.0;  ///< time at the travel limit [s]
  double median_rate = 0.0, worst_rate = 0.0;      ///< time at the rate limit [s]
  double median_tv = 0.0, worst_tv = 0.0;          ///< steady-flight total variation [rad]
  /// Fraction of each switch window (after the first) spent at a limit: median, worst.
  double median_window_limit = 0.0, worst_window_limit = 0.0;
};

/// \brief Effort of `runs` (one mode's runs over a family); lost runs count by what they did.
EffortSummary summarizeEffort(const std::vector<RunDigest>& runs);

/// \brief A regime the limited elevator can hold: the elevator deflection that trims the plant
/// x_dot = A x + B (theta^T x + u) + B1r r at x = x_ref_ss (the reference model's steady state
/// for the reference r, where an adaptive controller that tracks it settles) is
/// u_trim = v - theta^T x_ref_ss, with v = -K x_ref_ss the baseline's input there;
/// |u_trim| <= fraction * max_deflection for every |r| <= r_max (it is linear in r).
struct TrimCheck {
  Eigen::VectorXd x_per_r;  ///< x_ref_ss for r = 1
  double v_per_r = 0.0;     ///< v for r = 1
  double r_max = 0.0;       ///< largest |r| of the family
  double limit = 0.0;       ///< fraction * max_deflection [rad]
  /// \brief The trim deflection of `theta` at r = r_max [rad].
  double trim(const Eigen::VectorXd& theta) const;
  bool holds(const Eigen::VectorXd& theta) const { return std::abs(trim(theta)) <= limit; }
};

/// \brief The trim check of the closed loop A_m = A - B K, B1r: x_ref_ss = -A_m^{-1} B1r r.
/// Throws std::invalid_argument when A_m is singular.
TrimCheck makeTrimCheck(const Eigen::MatrixXd& A, const Eigen::VectorXd& B,
                        const Eigen::VectorXd& B1r, const Eigen::RowVectorXd& K, double r_max,
                        double limit);

/// \brief The largest excursion `samples` samples of white noise of standard deviation `sigma`
/// reach, by its usual bound sigma sqrt(2 ln(2 samples)) (the expected largest |noise| lies a
/// little below: 4.0 sigma against the bound's 4.55 sigma for 16000 samples) [as sigma].
double noisePeak(double sigma, double samples);

/// \brief A switch window is quiet when rac's peak |e| there is at most this many times the
/// sensor noise's largest excursion over the window: what the switch adds to rac's peak is then
/// no larger than the noise alone (a signal-to-noise ratio of one at most).
inline constexpr double kQuietFactor = 2.0;

/// \brief The windows (0 = the first segment) of `s` whose switch the sensor noise hides: rac's
/// measured peak |e| at most `factor` x noisePeak(sigma, the window's samples at `dt`). In such a
/// window every mode's peak is the noise's largest excursion plus a few hundredths of a mrad of
/// its own, and a peak ratio compares two noise realisations. None when sigma or factor is 0;
/// window 0 never (no switch). sigma: the noise on the measured output (alpha) [rad].
std::vector<bool> quietWindows(const Scenario& s, double dt, double sigma, const RunDigest& rac,
                               double factor = kQuietFactor);

/// \brief One mode against rac over a family (docs/spec.md "Beyond the paper"). The ratios judge
/// the windows that are not quiet (quietWindows); `quiet` counts the repeated ones left out.
struct FamilySummary {
  int windows = 0;                ///< repeated-switch windows compared
  int quiet = 0;                  ///< repeated-switch windows left out as quiet
  double frac_better = 0.0;       ///< peak ratio < 1
  double frac_halved = 0.0;       ///< peak ratio <= 0.5
  double median_ratio = 0.0;      ///< median peak ratio
  double worst_ratio = 0.0;       ///< largest peak ratio
  double all_median_ratio = 0.0;  ///< median over every switch window (new regimes too)
  double all_worst_ratio = 0.0;
  double worst_iae_ratio = 0.0;  ///< largest whole-run IAE ratio to rac
  int iae_over = 0;              ///< scenarios with IAE more than 5 % above rac's
  double worst_u_rac = 0.0;      ///< largest max|u| ratio to rac
  double worst_u_oracle = 0.0;   ///< largest max|u| ratio to the oracle (0 without oracle)
  std::vector<double> ratios;    ///< every repeated-window ratio (for figures)
  int lost_runs = 0;  ///< runs whose IAE is not finite: their windows from the blow-up count inf
};

/// \brief Compare `mode` with `rac` scenario by scenario; `oracle` may be null; `quiet` (may be
/// null: none) each scenario's quiet windows, left out of every ratio (but a window the mode's
/// run was lost in, or after: that counts inf all the same).
FamilySummary summarizeFamily(const std::vector<std::vector<bool>>& repeated,
                              const std::vector<RunDigest>& rac, const std::vector<RunDigest>& mode,
                              const std::vector<RunDigest>* oracle,
                              const std::vector<std::vector<bool>>* quiet = nullptr);

/// \brief The revisit criterion: a mode's peak |e| in a window that switches back into a known
/// regime within this factor of the oracle's peak in the same window (the oracle is told the true
/// theta at each switch, so it bounds what a recall of the regime can achieve).
constexpr double kRevisitTolerance = 1.2;

/// \brief A mode's peak |e| over the oracle's in one revisit window (a repeated window,
/// repeatedWindows: its theta equals that of an earlier segment of the scenario).
struct RevisitRatio {
  int window = 0;      ///< the window (0 = the first segment)
  double ratio = 0.0;  ///< peak |e| of the mode / peak |e| of the oracle
};

/// \brief Every revisit window of one scenario, in order, with its peak ratio of `mode` to
/// `oracle`. From the window a lost run (IAE not finite, as in summarizeFamily) blew up in, a
/// lost mode counts inf (the worst), a lost oracle with the mode still flying 0. With `quiet`,
/// its quiet windows are left out, but those from the mode's loss.
std::vector<RevisitRatio> revisitRatios(const std::vector<bool>& repeated, const RunDigest& oracle,
                                        const RunDigest& mode,
                                        const std::vector<bool>* quiet = nullptr);

/// \brief One mode against the oracle over the revisit windows of a family.
struct RevisitSummary {
  int count = 0;               ///< revisit windows compared
  double median = 0.0;         ///< median peak ratio to the oracle
  double worst = 0.0;          ///< largest peak ratio to the oracle
  double within = 0.0;         ///< fraction with ratio <= kRevisitTolerance
  std::vector<double> ratios;  ///< every revisit ratio, scenario by scenario (for figures)
};

/// \brief revisitRatios of every scenario of the family, summarized (count 0, the rest 0, when
/// there is no revisit); `quiet` (may be null) as in summarizeFamily.
RevisitSummary summarizeRevisits(const std::vector<std::vector<bool>>& repeated,
                                 const std::vector<RunDigest>& oracle,
                                 const std::vector<RunDigest>& mode,
                                 const std::vector<std::vector<bool>>* quiet = nullptr);

}  // namespace preadaptive_mrac
