#include "preadaptive_mrac/core/plant.hpp"

#include <algorithm>
#include <cmath>

#include "preadaptive_mrac/core/params.hpp"

namespace preadaptive_mrac {

PlantConfig PlantConfig::read(ParamReader& r, const std::string& prefix) {
  PlantConfig c;
  c.A = r.getMatrix(prefix + ".A");
  const int n = static_cast<int>(c.A.rows());
  if (c.A.rows() != c.A.cols() && c.A.size() > 0)
    r.fail(prefix + ".A", "must be square (n x n), got " + std::to_string(c.A.rows()) + " x " +
                              std::to_string(c.A.cols()));
  const int want = (c.A.rows() == c.A.cols() && n > 0) ? n : -1;
  c.B = r.getVector(prefix + ".B", want);
  c.B1r = r.getVector(prefix + ".B1r", want);
  c.x0 = r.getVector(prefix + ".x0", want);
  c.output_index = static_cast<int>(r.getInt(prefix + ".output_index"));
  if (r.has(prefix + ".actuator")) {
    const std::string a = prefix + ".actuator";
    c.actuator.enabled = r.getBool(a + ".enabled");
    c.actuator.max_deflection = r.getDouble(a + ".max_deflection");
    c.actuator.max_rate = r.getDouble(a + ".max_rate");
    for (const char* k : {".max_deflection", ".max_rate"})
      if (r.usable(a + k) && !(r.getDouble(a + k) > 0.0))
        r.fail(a + k, "must be > 0, got " + formatNumber(r.getDouble(a + k)));
  } else {
    r.noteDefault(prefix + ".actuator", "absent (no elevator limits)");
  }
  if (r.has(prefix + ".noise")) {
    const std::string nk = prefix + ".noise";
    c.noise.std = r.getVector(nk + ".std", want);
    for (Eigen::Index i = 0; i < c.noise.std.size(); ++i)
      if (r.usable(nk + ".std") && !(c.noise.std[i] >= 0.0))
        r.fail(nk + ".std", "must be >= 0, got " + formatNumber(c.noise.std[i]));
    const std::int64_t seed = r.getInt(nk + ".seed");
    if (seed < 0) r.fail(nk + ".seed", "must be >= 0");
    c.noise.seed = static_cast<std::uint64_t>(seed < 0 ? 0 : seed);
  } else {
    r.noteDefault(prefix + ".noise", "absent (no measurement noise)");
  }
  // The operating point documents where A and B come from; nothing reads it.
  r.markUsed(prefix + ".operating_point");
  r.markUsed(prefix + ".description");
  c.validate(r, prefix);
  return c;
}

void PlantConfig::validate(ParamReader& r, const std::string& prefix) const {
  const int n = static_cast<int>(A.rows());
  if (n == 0) return;  // already reported by the reader
  if (n > kMaxStates)
    r.fail(prefix + ".A", "at most " + std::to_string(kMaxStates) + " states are supported, got " +
                              std::to_string(n));
  if (r.usable(prefix + ".output_index") && (output_index < 0 || output_index >= n))
    r.fail(prefix + ".output_index",
           "must be in [0, " + std::to_string(n - 1) + "], got " + std::to_string(output_index));
  if (r.usable(prefix + ".B") && B.size() == n && B.isZero(0.0))
    r.fail(prefix + ".B", "must not be all zero");
}

double ActuatorLimits::apply(double u, double u_prev, double dt) const {
  if (!enabled) return u;
  const double step = max_rate * dt;
  double v = std::min(std::max(u, u_prev - step), u_prev + step);
  return std::min(std::max(v, -max_deflection), max_deflection);
}

double GaussianSource::next() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  // Box-Muller on two uniforms in (0, 1] built from the generator's 53 high bits.
  const double u1 = (static_cast<double>(gen_() >> 11) + 1.0) * (1.0 / 9007199254740992.0);
  const double u2 = static_cast<double>(gen_() >> 11) * (1.0 / 9007199254740992.0);
  const double rad = std::sqrt(-2.0 * std::log(u1));
  const double ang = 6.283185307179586 * u2;
  spare_ = rad * std::sin(ang);
  has_spare_ = true;
  return rad * std::cos(ang);
}

Plant::Plant(const PlantConfig& cfg)
    : A_(cfg.A), B_(cfg.B), B1r_(cfg.B1r), x0_(cfg.x0), x_(cfg.x0), out_(cfg.output_index) {
  const int n = cfg.n();
  k1_.setZero(n);
  k2_.setZero(n);
  k3_.setZero(n);
  k4_.setZero(n);
  tmp_.setZero(n);
}

void Plant::derivative(const Vec& x, const Vec& theta, double u, double r, Vec* xdot) const {
  xdot->noalias() = A_.lazyProduct(x);
  *xdot += B_ * (theta.dot(x) + u) + B1r_ * r;
}

void Plant::step(double dt, const Vec& theta, double u, double r) {
  derivative(x_, theta, u, r, &k1_);
  tmp_ = x_ + 0.5 * dt * k1_;
  derivative(tmp_, theta, u, r, &k2_);
  tmp_ = x_ + 0.5 * dt * k2_;
  derivative(tmp_, theta, u, r, &k3_);
  tmp_ = x_ + dt * k3_;
  derivative(tmp_, theta, u, r, &k4_);
  x_ += (dt / 6.0) * (k1_ + 2.0 * k2_ + 2.0 * k3_ + k4_);
}

}  // namespace preadaptive_mrac
