#include "preadaptive_mrac/core/sim/envelope.hpp"

#include <cmath>
#include <cstdio>

#include "preadaptive_mrac/core/schema/params.hpp"

namespace preadaptive_mrac {

namespace {
// A time for a person: step * dt carries rounding (5.0040000000000004); microseconds suffice.
std::string formatTime(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6f", t);
  std::string s(buf);
  s.erase(s.find_last_not_of('0') + 1);
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s;
}
}  // namespace

std::string EnvelopeExit::describe() const {
  if (!exited) return "";
  std::string s = "t = " + formatTime(t) + " s (step " + std::to_string(step) + "): ";
  if (bound == "non_finite") {
    s += "the state or command is not finite (u = " + formatNumber(u_command) + ", x = [";
    for (Eigen::Index i = 0; i < x.size(); ++i) s += (i ? ", " : "") + formatNumber(x[i]);
    return s + "])";
  }
  std::string end;
  if (non_finite && non_finite_t > t)
    end = "; the state was not finite at t = " + formatTime(non_finite_t) + " s";
  const char* what = bound == "alpha" ? "|alpha|" : bound == "pitch_rate" ? "|q|" : "|u|";
  const char* unit = bound == "pitch_rate" ? " rad/s" : " rad";
  return s + what + " = " + formatNumber(value) + unit + " > " + formatNumber(limit) + unit +
         " (plant.envelope." + key + ")" + end;
}

void EnvelopeMonitor::checkStateBeyond(std::int64_t step, double t, const Vec& x, double u,
                                       const PlantConditions& c) {
  if (!x.allFinite()) {
    markNonFinite(t);
    record(step, t, "non_finite", "", NAN, 0.0, x, u, c);
    return;
  }
  if (!env_.enabled || exit_.exited) return;
  if (alpha_ < x.size() && !(std::abs(x[alpha_]) <= env_.max_alpha))
    record(step, t, "alpha", "max_alpha", std::abs(x[alpha_]), env_.max_alpha, x, u, c);
  else if (x.size() > 2 && !(std::abs(x[2]) <= env_.max_pitch_rate))
    record(step, t, "pitch_rate", "max_pitch_rate", std::abs(x[2]), env_.max_pitch_rate, x, u, c);
}

void EnvelopeMonitor::record(std::int64_t step, double t, const char* bound, const char* key,
                             double value, double limit, const Vec& x, double u,
                             const PlantConditions& c) {
  if (exit_.exited) return;            // the first exit only
  alpha_limit_ = q_limit_ = HUGE_VAL;  // from now on only finiteness matters
  // (non_finite and its time are kept: a non-finite command is flagged before it is recorded)
  exit_ = EnvelopeExit{true,
                       step,
                       t,
                       bound,
                       key,
                       value,
                       limit,
                       x,
                       u,
                       c,
                       ConditionRows{true, engine_},
                       exit_.non_finite,
                       exit_.non_finite_t};
}

}  // namespace preadaptive_mrac
