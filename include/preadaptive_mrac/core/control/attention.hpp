#pragma once
/// \file attention.hpp
/// \brief The attention function of the paper (eq. attention), with optional debounce and
/// hysteresis.

namespace preadaptive_mrac {

/// \brief Attention function (eq. attention) with the phase state of docs/spec.md.
///
/// Two options against noise, both off by default (the paper's behaviour): `confirm_samples`
/// N > 0 accepts a crossing only when |e| stays on the new side for N more samples, and checks
/// the rate condition at the confirming sample; `hysteresis` h > 0 puts the recovery
/// threshold at c_e - h.
class Attention {
 public:
  enum class Result { kNone, kOnset, kRecovered, kIgnoredOnset, kIgnoredRecovery };
  Attention(double c_e, double c_ed, int confirm_samples = 0, double hysteresis = 0.0)
      : c_e_(c_e), c_ed_(c_ed), confirm_(confirm_samples), hyst_(hysteresis) {}
  /// \brief New thresholds between two samples. The last sample is re-evaluated against them,
  /// so the change itself is no crossing; a changed confirm_samples drops pending crossings.
  void setThresholds(double c_e, double c_ed, int confirm_samples, double hysteresis);
  /// \brief Evaluate one sample of e and its estimated rate.
  Result update(double e, double e_dot);
  bool phaseActive() const { return active_; }
  /// \brief Enter a phase without an onset (an externally triggered phase).
  void forceActive() { active_ = true; }
  /// \brief Leave the phase (a strategy's own recovery).
  void endPhase() { active_ = false; }
  void reset() {
    primed_ = false;
    active_ = false;
    up_count_ = down_count_ = -1;
  }

 private:
  Result decideUp(double e_dot);
  Result decideDown(double e_dot);
  double c_e_, c_ed_;
  int confirm_;
  double hyst_;
  bool primed_ = false, active_ = false;
  double s_prev_ = 0.0, d_prev_ = 0.0;   // |e| - c_e and |e| - (c_e - h) at the last sample
  double abs_e_prev_ = 0.0;              // |e| at the last sample (setThresholds)
  int up_count_ = -1, down_count_ = -1;  // samples held since a crossing; -1 when none pending
};

}  // namespace preadaptive_mrac
