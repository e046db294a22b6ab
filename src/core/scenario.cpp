#include "preadaptive_mrac/core/scenario.hpp"

#include <cmath>

#include "preadaptive_mrac/core/params.hpp"

namespace preadaptive_mrac {

double Scenario::endTime() const { return theta.empty() ? 0.0 : theta.back().until; }

const Eigen::VectorXd& Scenario::thetaAt(double t) const {
  for (const auto& s : theta)
    if (t <= s.until) return s.theta;
  return theta.back().theta;
}

double Scenario::rAt(double t) const {
  for (const auto& s : reference)
    if (t <= s.until) return s.r;
  return reference.back().r;
}

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

Scenario Scenario::read(ParamReader& r, int n, const std::string& prefix) {
  Scenario sc;
  sc.name = r.getString(prefix + ".name");
  sc.description = r.getString(prefix + ".description", "");

  const std::string tk = prefix + ".theta";
  const int nt = r.getListSize(tk);
  double prev = 0.0;
  for (int i = 0; i < nt; ++i) {
    const std::string seg = tk + "." + std::to_string(i);
    ThetaSegment s;
    s.until = readUntil(r, seg + ".until", prev);
    prev = std::max(prev, s.until);
    const bool has_scale = r.has(seg + ".scale"), has_vec = r.has(seg + ".theta");
    if (has_scale == has_vec) {
      r.fail(seg, "give exactly one of 'scale' (theta = scale * ones) or 'theta' (a list of " +
                      std::to_string(n) + " numbers)");
      s.theta = Eigen::VectorXd::Zero(n);
    } else if (has_scale) {
      s.theta = Eigen::VectorXd::Constant(n, r.getDouble(seg + ".scale"));
    } else {
      s.theta = r.getVector(seg + ".theta", n);
    }
    sc.theta.push_back(s);
  }

  const std::string rk = prefix + ".reference";
  if (!r.has(rk)) {
    r.markUsed(rk);
    sc.reference.push_back({sc.endTime(), 0.1});
  } else {
    const int nr = r.getListSize(rk);
    double rprev = 0.0;
    for (int i = 0; i < nr; ++i) {
      const std::string seg = rk + "." + std::to_string(i);
      RefSegment s;
      s.until = readUntil(r, seg + ".until", rprev);
      rprev = std::max(rprev, s.until);
      s.r = r.getDouble(seg + ".r");
      sc.reference.push_back(s);
    }
    if (!sc.reference.empty() && !sc.theta.empty() && sc.reference.back().until < sc.endTime())
      r.fail(rk, "the last reference segment must reach the scenario end " +
                     formatNumber(sc.endTime()) + " s, it ends at " +
                     formatNumber(sc.reference.back().until) + " s");
  }
  return sc;
}

}  // namespace preadaptive_mrac
