#include "preadaptive_mrac/core/plant.hpp"

#include <algorithm>
#include <cmath>

#include "preadaptive_mrac/core/params.hpp"
#include "preadaptive_mrac/core/small_ops.hpp"

namespace preadaptive_mrac {

namespace {
// An optional duration [s] that must be a finite number >= 0; 0 when absent.
double readNonNegative(ParamReader& r, const std::string& key) {
  if (!r.has(key)) return 0.0;
  const double v = r.getDouble(key);
  if (r.usable(key) && !(v >= 0.0 && std::isfinite(v)))
    r.fail(key, "must be a finite number >= 0 [s], got " + formatNumber(v));
  return v;
}
}  // namespace

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
    // Delay and lag alone need no limits: the limit keys are required once any of them (or
    // neither delay nor lag) is given, as before.
    const bool dynamics_only = (r.has(a + ".delay") || r.has(a + ".time_constant")) &&
                               !r.has(a + ".enabled") && !r.has(a + ".max_deflection") &&
                               !r.has(a + ".max_rate");
    if (!dynamics_only) {
      c.actuator.enabled = r.getBool(a + ".enabled");
      c.actuator.max_deflection = r.getDouble(a + ".max_deflection");
      c.actuator.max_rate = r.getDouble(a + ".max_rate");
      for (const char* k : {".max_deflection", ".max_rate"})
        if (r.usable(a + k) && !(r.getDouble(a + k) > 0.0))
          r.fail(a + k, "must be > 0, got " + formatNumber(r.getDouble(a + k)));
    }
    // Absent = 0 without a note in the defaults list: a run without the new keys must report
    // exactly what it reported before them.
    c.dynamics.delay = readNonNegative(r, a + ".delay");
    // The delay line holds delay / dt commands: an hour is longer than any run.
    if (c.dynamics.delay > kMaxDelay)
      r.fail(a + ".delay", "must be at most " + formatNumber(kMaxDelay) + " s, got " +
                               formatNumber(c.dynamics.delay));
    c.dynamics.time_constant = readNonNegative(r, a + ".time_constant");
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
  if (r.has(prefix + ".turbulence")) {
    const std::string t = prefix + ".turbulence";
    c.turbulence.enabled = r.getBool(t + ".enabled");
    c.turbulence.sigma_w = r.getDouble(t + ".sigma_w");
    if (r.usable(t + ".sigma_w") &&
        !(c.turbulence.sigma_w >= 0.0 && std::isfinite(c.turbulence.sigma_w)))
      r.fail(t + ".sigma_w",
             "must be a finite number >= 0 [m/s], got " + formatNumber(c.turbulence.sigma_w));
    c.turbulence.length_scale = r.getDouble(t + ".length_scale");
    if (r.usable(t + ".length_scale") &&
        !(c.turbulence.length_scale > 0.0 && std::isfinite(c.turbulence.length_scale)))
      r.fail(t + ".length_scale",
             "must be a finite number > 0 [m], got " + formatNumber(c.turbulence.length_scale));
    const std::int64_t seed = r.getInt(t + ".seed");
    if (seed < 0) r.fail(t + ".seed", "must be >= 0");
    c.turbulence.seed = static_cast<std::uint64_t>(seed < 0 ? 0 : seed);
  }
  // The operating point documents where A and B come from; its airspeed U is the V of the
  // turbulence filter (required when turbulence is on).
  const std::string uk = prefix + ".operating_point.U";
  if (r.has(uk)) {
    c.airspeed = r.getDouble(uk);
    if (r.usable(uk) && !(c.airspeed > 0.0 && std::isfinite(c.airspeed)))
      r.fail(uk, "must be a finite number > 0 [m/s], got " + formatNumber(c.airspeed));
  } else if (c.turbulence.enabled) {
    r.fail(uk, "required when plant.turbulence.enabled is true (the gust filter's airspeed V)");
  }
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
  three_ = fastThree(n);
  if (three_) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) a3_[3 * i + j] = A_(i, j);
      b3_[i] = B_[i];
      b1r3_[i] = B1r_[i];
    }
  }
}

void Plant::derivative(const Vec& x, const Vec& theta, double u, double r, Vec* xdot) const {
  xdot->noalias() = A_.lazyProduct(x);
  *xdot += B_ * (theta.dot(x) + u) + B1r_ * r;
}

void Plant::step(double dt, const Vec& theta, double u, double r) {
  if (three_)
    step3(dt, theta, u, r);
  else
    stepGeneric(dt, theta, u, r);
}

void Plant::stepDisturbed(double dt, const Vec& theta, double u, double r, const Vec& d) {
  derivative(x_, theta, u, r, &k1_);
  k1_ += d;
  tmp_ = x_ + 0.5 * dt * k1_;
  derivative(tmp_, theta, u, r, &k2_);
  k2_ += d;
  tmp_ = x_ + 0.5 * dt * k2_;
  derivative(tmp_, theta, u, r, &k3_);
  k3_ += d;
  tmp_ = x_ + dt * k3_;
  derivative(tmp_, theta, u, r, &k4_);
  k4_ += d;
  x_ += (dt / 6.0) * (k1_ + 2.0 * k2_ + 2.0 * k3_ + k4_);
}

void Plant::stepGeneric(double dt, const Vec& theta, double u, double r) {
  derivative(x_, theta, u, r, &k1_);
  tmp_ = x_ + 0.5 * dt * k1_;
  derivative(tmp_, theta, u, r, &k2_);
  tmp_ = x_ + 0.5 * dt * k2_;
  derivative(tmp_, theta, u, r, &k3_);
  tmp_ = x_ + dt * k3_;
  derivative(tmp_, theta, u, r, &k4_);
  x_ += (dt / 6.0) * (k1_ + 2.0 * k2_ + 2.0 * k3_ + k4_);
}

// stepGeneric() written out for three states. Floating-point addition is not associative, so
// every sum is formed in the order Eigen forms it for n = 3: A x row by row from column 0 up
// (the lazy product), theta . x as (t0 x0 + t1 x1) + t2 x2 (its dot product), then
// A x + (B s + B1r r); the RK4 combination as in stepGeneric(). No -ffast-math, and x86-64
// without -mfma has no fused multiply-add to contract into; test_plant compares the two paths
// bit for bit on whatever target it is built for.
void Plant::step3(double dt, const Vec& theta, double u, double r) {
  const double* a = a3_;
  const double th0 = theta[0], th1 = theta[1], th2 = theta[2];
  const auto f = [&](const double* x, double* xd) {
    const double s = ((th0 * x[0] + th1 * x[1]) + th2 * x[2]) + u;
    for (int i = 0; i < 3; ++i) {
      const double ax = (a[3 * i] * x[0] + a[3 * i + 1] * x[1]) + a[3 * i + 2] * x[2];
      xd[i] = ax + (b3_[i] * s + b1r3_[i] * r);
    }
  };
  const double x[3] = {x_[0], x_[1], x_[2]};
  const double h2 = 0.5 * dt;
  double k1[3], k2[3], k3[3], k4[3], tmp[3];
  f(x, k1);
  for (int i = 0; i < 3; ++i) tmp[i] = x[i] + h2 * k1[i];
  f(tmp, k2);
  for (int i = 0; i < 3; ++i) tmp[i] = x[i] + h2 * k2[i];
  f(tmp, k3);
  for (int i = 0; i < 3; ++i) tmp[i] = x[i] + dt * k3[i];
  f(tmp, k4);
  const double w = dt / 6.0;
  for (int i = 0; i < 3; ++i) x_[i] = x[i] + w * (((k1[i] + 2.0 * k2[i]) + 2.0 * k3[i]) + k4[i]);
}

}  // namespace preadaptive_mrac
