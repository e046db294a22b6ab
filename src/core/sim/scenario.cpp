#include "preadaptive_mrac/core/sim/scenario.hpp"

#include <cmath>

#include "preadaptive_mrac/core/schema/param_table.hpp"
#include "preadaptive_mrac/core/schema/params.hpp"

namespace preadaptive_mrac {

const std::array<Scenario::FaultKey, 3> Scenario::kFaultKeys = {{
    {"cg_shift", -0.3, 0.3, &FaultSegment::cg_shift, "the CG shift [fraction of the chord, + aft]"},
    {"elevator_effectiveness", 0.0, 2.0, &FaultSegment::elevator_effectiveness,
     "the elevator effectiveness multiplier"},
    {"pitch_damping", 0.0, 2.0, &FaultSegment::pitch_damping, "the pitch damping multiplier"},
}};

double Scenario::endTime() const { return theta.empty() ? 0.0 : theta.back().until; }

namespace {
// The first segment from `from` on with t <= until, else the last.
template <typename Segment>
size_t segmentFrom(const std::vector<Segment>& segs, double t, size_t from) {
  for (size_t i = from; i < segs.size(); ++i)
    if (t <= segs[i].until) return i;
  return segs.empty() ? 0 : segs.size() - 1;
}
}  // namespace

size_t Scenario::thetaIndexFrom(double t, size_t from) const { return segmentFrom(theta, t, from); }

size_t Scenario::rIndexFrom(double t, size_t from) const { return segmentFrom(reference, t, from); }

size_t Scenario::effectivenessIndexFrom(double t, size_t from) const {
  return segmentFrom(effectiveness, t, from);
}

size_t Scenario::faultIndexFrom(double t, size_t from) const {
  return segmentFrom(faults, t, from);
}

double Scenario::effectivenessAt(double t) const {
  return effectiveness.empty() ? 1.0 : effectiveness[effectivenessIndexFrom(t, 0)].value;
}

const Eigen::VectorXd& Scenario::thetaAt(double t) const {
  return theta[thetaIndexFrom(t, 0)].theta;
}

double Scenario::rAt(double t) const { return reference[rIndexFrom(t, 0)].r; }

std::vector<double> Scenario::switchTimes() const {
  std::vector<double> out;
  for (size_t i = 0; i + 1 < theta.size(); ++i) out.push_back(theta[i].until);
  return out;
}

namespace {
// `until` of segment i, checked to be > 0 and increasing.
double readUntil(ParamReader& r, const std::string& key, double prev) {
  const double until = r.getDouble(key);
  if (r.usable(key) && !(until > prev))
    r.fail(key, "segments must end at increasing times > " + formatNumber(prev) + ", got " +
                    formatNumber(until));
  return until;
}
}  // namespace

namespace {
// One list of segments under `key`: each entry's `until` is checked to increase, then
// `value(entry_key)` reads the rest; one loop for theta and r.
template <typename Segment, typename ReadValue>
std::vector<Segment> readSegments(ParamReader& r, const std::string& key, ReadValue value) {
  std::vector<Segment> out;
  const int count = r.getListSize(key);
  double prev = 0.0;
  for (int i = 0; i < count; ++i) {
    const std::string seg = key + "." + std::to_string(i);
    Segment s;
    s.until = readUntil(r, seg + ".until", prev);
    prev = std::max(prev, s.until);
    value(seg, &s);
    out.push_back(s);
  }
  return out;
}
}  // namespace

Scenario Scenario::read(ParamReader& r, int n, const std::string& prefix) {
  Scenario sc;
  // The scalars (name, description) from the generated struct; the schedules, lists of
  // segments with rules across them (increasing ends, one of scale and theta), by hand.
  readChecked(r, prefix, static_cast<ScenarioParams*>(&sc));

  sc.theta = readSegments<ThetaSegment>(
      r, prefix + ".theta", [&](const std::string& seg, ThetaSegment* s) {
        const bool has_scale = r.has(seg + ".scale"), has_vec = r.has(seg + ".theta");
        if (has_scale == has_vec) {
          r.fail(seg, "give exactly one of 'scale' (theta = scale * ones) or 'theta' (a list of " +
                          std::to_string(n) + " numbers)");
          s->theta = Eigen::VectorXd::Zero(n);
        } else if (has_scale) {
          s->theta = Eigen::VectorXd::Constant(n, r.getDouble(seg + ".scale"));
        } else {
          s->theta = r.getVector(seg + ".theta", n > 0 ? n : -1);
        }
      });

  const std::string rk = prefix + ".reference";
  if (!r.has(rk)) {
    r.markUsed(rk);
    sc.reference.push_back({sc.endTime(), 0.1});
    r.noteDefault(rk, "absent (r = 0.1 rad throughout)");
  } else {
    sc.reference = readSegments<RefSegment>(
        r, rk, [&](const std::string& seg, RefSegment* s) { s->r = r.getDouble(seg + ".r"); });
    if (!sc.reference.empty() && !sc.theta.empty() && sc.reference.back().until < sc.endTime())
      r.fail(rk, "the last reference segment must reach the scenario end " +
                     formatNumber(sc.endTime()) + " s, it ends at " +
                     formatNumber(sc.reference.back().until) + " s");
  }
  // Absent: Lambda = 1 throughout, with no note in the defaults list (a run without the key
  // reports exactly what it reported before the key existed).
  const std::string ek = prefix + ".effectiveness";
  if (r.has(ek)) {
    sc.effectiveness = readSegments<EffectivenessSegment>(
        r, ek, [&](const std::string& seg, EffectivenessSegment* s) {
          s->value = r.getDouble(seg + ".value");
          if (r.usable(seg + ".value") && !(s->value > 0.0 && s->value <= 2.0))
            r.fail(seg + ".value",
                   "elevator effectiveness must be in (0, 2], got " + formatNumber(s->value));
        });
    if (!sc.effectiveness.empty() && !sc.theta.empty() &&
        sc.effectiveness.back().until < sc.endTime())
      r.fail(ek, "the last effectiveness segment must reach the scenario end " +
                     formatNumber(sc.endTime()) + " s, it ends at " +
                     formatNumber(sc.effectiveness.back().until) + " s");
  }
  // Absent: the nominal aircraft, no note (as the effectiveness schedule).
  const std::string fk = prefix + ".faults";
  if (r.has(fk)) {
    sc.faults = readSegments<FaultSegment>(r, fk, [&](const std::string& seg, FaultSegment* s) {
      for (const FaultKey& f : kFaultKeys) {
        const std::string k = seg + "." + f.name;
        if (!r.has(k)) continue;
        double& v = s->*f.field;
        v = r.getDouble(k);
        if (r.usable(k) && !(v >= f.lo && v <= f.hi))
          r.fail(k, std::string(f.what) + " must be in [" + formatNumber(f.lo) + ", " +
                        formatNumber(f.hi) + "], got " + formatNumber(v));
      }
    });
    if (!sc.faults.empty() && !sc.theta.empty() && sc.faults.back().until < sc.endTime())
      r.fail(fk, "the last fault segment must reach the scenario end " +
                     formatNumber(sc.endTime()) + " s, it ends at " +
                     formatNumber(sc.faults.back().until) + " s");
  }
  return sc;
}

}  // namespace preadaptive_mrac
