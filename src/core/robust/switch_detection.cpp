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

int excursionChangePoint(const double* S, int n) {
  double best = 0.0;
  for (int j = 0; j < n; ++j) best = std::max(best, S[j]);
  int m = n;
  for (int j = 0; j < n; ++j)
    if (S[j] >= 0.9 * best) {
      m = j + 1;
      break;
    }
  return std::max(m, std::min(2, n));
}

int kinkChangePoint(const double* S, int n, double min_gain) {
  if (n < 8) return excursionChangePoint(S, n);
  // Points J = 0..n, S_0 = 0 (no sample yet), so a change one sample ago shows as a kink too.
  // The line c + a J first; the kink's regressor g_J = (J - m)+ is then judged by what it adds
  // to it (Frisch-Waugh): b = g^T S_perp / |g_perp|^2, and the residual sum of squares falls by
  // (g^T S_perp)^2 / |g_perp|^2, with S_perp = S - line and g_perp = g less its own line. The
  // sums of g, g^2 and J g have closed forms; those of S_perp and J S_perp beyond m are summed
  // from the oldest sample back, so the search is one pass.
  const double N = n + 1.0, s1 = 0.5 * n * (n + 1.0), s2 = n * (n + 1.0) * (2.0 * n + 1.0) / 6.0;
  double sy = 0.0, sjy = 0.0, syy = 0.0;
  for (int J = 1; J <= n; ++J) {
    sy += S[J - 1];
    sjy += J * S[J - 1];
    syy += S[J - 1] * S[J - 1];
  }
  const double det = N * s2 - s1 * s1;
  const double a = (N * sjy - s1 * sy) / det, c = (sy - a * s1) / N;
  double t0 = 0.0, t1 = 0.0;  // sums of S_perp and J S_perp over J > m
  // A kink must explain more than noise (and rounding) does.
  double best_gain = std::max(min_gain, 1e-12 * syy);
  int best = -1;
  for (int m = n - 1; m >= 1; --m) {
    const double sp = S[m] - (c + a * (m + 1));  // J = m + 1 joins the sums beyond m
    t0 += sp;
    t1 += (m + 1) * sp;
    if (m > n - 2) continue;
    const double L = n - m;
    const double g1 = 0.5 * L * (L + 1.0), g2 = L * (L + 1.0) * (2.0 * L + 1.0) / 6.0;
    const double jg = m * g1 + g2;
    // |g_perp|^2 = g^T g - [g1 jg] (X^T X)^-1 [g1 jg]^T, X = [1 J].
    const double gg = g2 - (s2 * g1 * g1 - 2.0 * s1 * g1 * jg + N * jg * jg) / det;
    if (!(gg > 0.0)) continue;
    const double gs = t1 - m * t0;
    if (!(gs < 0.0)) continue;  // the newest samples must grow faster than those before
    const double gain = gs * gs / gg;
    if (gain > best_gain) {
      best_gain = gain;
      best = m;
    }
  }
  return best < 0 ? n : std::max(best, 2);
}

}  // namespace preadaptive_mrac
