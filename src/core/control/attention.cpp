#include "preadaptive_mrac/core/control/attention.hpp"

#include <cmath>

namespace preadaptive_mrac {

Attention::Result Attention::decideUp(double e_dot) {
  if (!(std::abs(e_dot) > c_ed_)) return Result::kNone;
  if (active_) return Result::kIgnoredOnset;
  active_ = true;
  return Result::kOnset;
}

Attention::Result Attention::decideDown(double e_dot) {
  if (!(std::abs(e_dot) < c_ed_)) return Result::kNone;
  if (!active_) return Result::kIgnoredRecovery;
  active_ = false;
  return Result::kRecovered;
}

void Attention::setThresholds(double c_e, double c_ed, int confirm_samples, double hysteresis) {
  if (confirm_samples != confirm_) up_count_ = down_count_ = -1;
  c_e_ = c_e;
  c_ed_ = c_ed;
  confirm_ = confirm_samples;
  hyst_ = hysteresis;
  if (primed_) {  // the last sample against the new thresholds: the change is no crossing
    s_prev_ = abs_e_prev_ - c_e_;
    d_prev_ = abs_e_prev_ - (c_e_ - hyst_);
  }
}

Attention::Result Attention::update(double e, double e_dot) {
  abs_e_prev_ = std::abs(e);
  const double s = std::abs(e) - c_e_;            // onset threshold
  const double d = std::abs(e) - (c_e_ - hyst_);  // recovery threshold
  if (!primed_) {
    primed_ = true;
    s_prev_ = s;
    d_prev_ = d;
    return Result::kNone;
  }
  const bool up = s_prev_ < 0.0 && s >= 0.0;
  const bool down = d_prev_ > 0.0 && d <= 0.0;
  s_prev_ = s;
  d_prev_ = d;
  if (confirm_ == 0) {  // the paper: decide at the crossing sample
    if (up) return decideUp(e_dot);
    if (down) return decideDown(e_dot);
    return Result::kNone;
  }
  // Debounced: a crossing is pending until |e| has stayed on its new side confirm_ samples.
  if (up) up_count_ = 0;
  if (down) down_count_ = 0;
  if (up_count_ >= 0) {
    if (s < 0.0) {
      up_count_ = -1;
    } else if (!up && ++up_count_ >= confirm_) {
      up_count_ = -1;
      return decideUp(e_dot);
    }
  }
  if (down_count_ >= 0) {
    if (d > 0.0) {
      down_count_ = -1;
    } else if (!down && ++down_count_ >= confirm_) {
      down_count_ = -1;
      return decideDown(e_dot);
    }
  }
  return Result::kNone;
}

}  // namespace preadaptive_mrac
