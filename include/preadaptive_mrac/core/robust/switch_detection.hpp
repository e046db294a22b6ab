#pragma once
/// \file switch_detection.hpp
/// \brief pa_robust's detection (robust_preadaptation.hpp, docs/research/robust.md) as pure
/// functions beside the decision (regime_decision.hpp): the noise level of the residual from
/// the change between adjacent windows, and the rules that turn the residuals into an onset,
/// a decision or a recovery. No state: the caller keeps the estimate and the counters, so a
/// detection seen in a run can be replayed from its numbers (test_switch_detection).

#include <cstdint>

#include "preadaptive_mrac/core/control/preadaptation.hpp"

namespace preadaptive_mrac {

/// \brief E|delta| / sigma for the change delta of two independent window residuals of
/// standard deviation sigma each: delta ~ N(0, 2 sigma^2), so E|delta| = 2 sigma / sqrt(pi).
inline constexpr double kMeanChangePerSigma = 1.1283791670955126;

/// \brief Detections needed before any trigger: the noise level must be known first.
inline constexpr int kMinNoiseBlocks = 16;

/// \brief The noise level of the residual, estimated from the mean absolute change of the
/// residual between adjacent detection windows: a constant mismatch cancels, noise does not.
struct NoiseEstimate {
  double mean_change = 0.0;  ///< estimate of E|delta| [rad]
  bool started = false;      ///< a first change has been seen
  int blocks = 0;            ///< changes folded in so far

  /// \brief The residual's standard deviation from noise alone [rad].
  double level() const { return mean_change / kMeanChangePerSigma; }
};

/// \brief Fold the change `delta` = |rho - rho_previous| of one window into the estimate: a
/// running mean over the first blocks, then an exponential one over `noise_time` [s]
/// (`window_time` [s] the detection window's length). Each step is clipped at four times the
/// estimate (at least `floor` [rad]), so a switch barely moves it.
NoiseEstimate foldNoiseChange(const NoiseEstimate& est, double delta, double window_time,
                              double noise_time, double floor);

/// \brief controller.robust's detection settings, and the windows in samples.
struct DetectionSettings {
  double threshold = 0.0;     ///< residual threshold [rad]
  double noise_factor = 0.0;  ///< the threshold is raised to noise_factor * noise level
  double window_time = 0.0;   ///< the short window's length [s]
  double noise_time = 0.0;    ///< time constant of the noise estimate [s]
  int detect_window = 1;      ///< short window [samples]
  int long_window = 0;        ///< long window (0: none) [samples]
  int min_dwell = 0;          ///< no onset sooner after the last one [samples]
  int quiet = 1;              ///< quiet samples that end a phase (recovery)
};

/// \brief The short window's trigger threshold max(threshold, noise_factor * noise) [rad].
double shortThreshold(const DetectionSettings& s, double noise_level);

/// \brief The long window's: its noise is endpoint noise, detect_window / long_window of the
/// short window's [rad].
double longThreshold(const DetectionSettings& s, double noise_level);

/// \brief Where the detection stands at sample k: the counts since the last onset and the
/// last verification's end [samples], the samples stored, and the phase.
struct DetectionClock {
  std::int64_t since_onset = 0;
  std::int64_t since_verified = 0;
  int stored = 0;
  bool noise_due = false;     ///< a window ends here: the noise estimate takes its change
  bool verifying = false;     ///< a switch is being verified
  bool decision_due = false;  ///< while verifying: a decision is due this sample
  bool phase_active = false;  ///< attention's phase runs (a recovery can end it)
};

/// \brief True when the long window may trigger: outside a verification, it is full and holds
/// only data since the last onset and since the last verification ended (older data was judged
/// against an estimate it did not have).
bool longWindowDue(const DetectionSettings& s, const DetectionClock& c);

/// \brief The residuals of the estimate [rad]: over the short window, over the window before it
/// (read only when noise_due) and over the long window (read only when longWindowDue()).
struct Residuals {
  double detect = 0.0;
  double previous = 0.0;
  double long_window = 0.0;
};

struct DetectionResult {
  Detection kind = Detection::kNone;
  bool long_trigger = false;  ///< kOnset came from the long window
  int quiet = 0;              ///< the quiet count after this sample
  NoiseEstimate noise;        ///< the noise estimate after this sample
};

/// \brief One sample's detection. The short threshold is the one the noise estimate `noise` gave
/// before this sample; then the window's change is folded in when noise_due. While verifying only
/// the decisions; no trigger before kMinNoiseBlocks noise blocks; an onset when the short
/// window's residual exceeds its threshold (no sooner than max(detect_window, min_dwell) after
/// the last), else when the long window's exceeds the long threshold of the updated noise level;
/// during a phase, a recovery after `quiet` samples under the short threshold. `quiet` is the
/// count so far.
DetectionResult detectSwitch(const Residuals& rho, const NoiseEstimate& noise,
                             const DetectionClock& c, int quiet, const DetectionSettings& s);

/// \brief Where a mismatch began, by the shortest span holding 90 % of the cumulative residual's
/// largest excursion. `S[J - 1]` is the sum of the J newest residuals (J = 1..n), signed so that
/// the trigger's direction is positive. Returns m, the newest samples taken as post-change (at
/// least min(2, n)). Exact without noise up to the 10 % it leaves out; in noise the largest
/// excursion holds the endpoint noise's peak, so 90 % of it can lie far before the change.
int excursionChangePoint(const double* S, int n);

/// \brief Where a mismatch began, by least squares: the cumulative residual of a mismatch that
/// began m samples ago grows with one slope since then and another before (the old estimate's
/// own small bias), plus endpoint noise, which is the same at every J (the sums telescope):
/// S_J = c + a J + b (J - m)+, with S_0 = 0. Returns the m in [1, n - 2] whose kink explains S
/// best with the newest samples growing faster than those before (b < 0), at least 2, when it
/// lowers the residual sum of squares by more than `min_gain` (what noise alone gives: of the
/// largest of these gains under noise of standard deviation s per sample, 99 % lie below 9.5
/// s^2 for n from 40 to 400); no such kink: n, the whole span is post-change. n < 8:
/// excursionChangePoint().
int kinkChangePoint(const double* S, int n, double min_gain);

}  // namespace preadaptive_mrac
