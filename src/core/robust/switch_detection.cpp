#include "preadaptive_mrac/core/robust/switch_detection.hpp"

#include <algorithm>
#include <cmath>

namespace preadaptive_mrac {

NoiseEstimate foldNoiseChange(const NoiseEstimate& est, double delta, double window_time,
                              double noise_time, double floor) {
  NoiseEstimate next = est;
  const double beta = std::max(1.0 / (est.blocks + 1), std::min(1.0, window_time / noise_time));
  if (!est.started) {
    next.mean_change = delta;
    next.started = true;
  } else {
    next.mean_change +=
        beta * (std::min(delta, std::max(4.0 * est.mean_change, floor)) - est.mean_change);
  }
  ++next.blocks;
  return next;
}

double shortThreshold(const DetectionSettings& s, double noise_level) {
  return std::max(s.threshold, s.noise_factor * noise_level);
}

double longThreshold(const DetectionSettings& s, double noise_level) {
  return std::max(s.threshold, s.noise_factor * noise_level * static_cast<double>(s.detect_window) /
                                   s.long_window);
}

bool longWindowDue(const DetectionSettings& s, const DetectionClock& c) {
  return !c.verifying && s.long_window > s.detect_window && c.stored >= s.long_window &&
         c.since_onset >= std::max(s.long_window, s.min_dwell) && c.since_verified >= s.long_window;
}

DetectionResult detectSwitch(const Residuals& rho, const NoiseEstimate& noise,
                             const DetectionClock& c, int quiet, const DetectionSettings& s) {
  DetectionResult r;
  r.quiet = quiet;
  r.noise = noise;
  const double thr = shortThreshold(s, noise.level());
  if (c.noise_due && !c.verifying) {
    r.noise = foldNoiseChange(noise, std::abs(rho.detect - rho.previous), s.window_time,
                              s.noise_time, s.threshold);
  }
  if (c.verifying) {
    r.kind = c.decision_due ? Detection::kDecision : Detection::kNone;
    return r;
  }
  if (r.noise.blocks < kMinNoiseBlocks) return r;
  if (std::abs(rho.detect) > thr && c.since_onset >= std::max(s.detect_window, s.min_dwell)) {
    r.kind = Detection::kOnset;
    return r;
  }
  if (longWindowDue(s, c) && std::abs(rho.long_window) > longThreshold(s, r.noise.level())) {
    r.kind = Detection::kOnset;
    r.long_trigger = true;
    return r;
  }
  if (c.phase_active) {
    r.quiet = std::abs(rho.detect) <= thr ? quiet + 1 : 0;
    if (r.quiet >= s.quiet) r.kind = Detection::kRecovered;
  }
  return r;
}

}  // namespace preadaptive_mrac
