#include "preadaptive_mrac/core/sim/plant.hpp"

#include <algorithm>
#include <cmath>

#include "preadaptive_mrac/core/schema/param_table.hpp"
#include "preadaptive_mrac/core/schema/params.hpp"
#include "preadaptive_mrac/core/small_ops.hpp"

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
  // The scalars come from the generated structs (params/plant.yaml: defaults, reading, ranges;
  // output_index and operating_point.U here, each part's below); the matrices and vectors
  // (sized by A) and the rules across keys stay by hand.
  readChecked(r, prefix, static_cast<PlantParams*>(&c));
  if (r.has(prefix + ".actuator")) {
    const std::string a = prefix + ".actuator";
    // Delay and lag alone need no limits: the limit keys are required once any of them (or
    // neither delay nor lag) is given.
    const bool dynamics_only = (r.has(a + ".delay") || r.has(a + ".time_constant")) &&
                               !r.has(a + ".enabled") && !r.has(a + ".max_deflection") &&
                               !r.has(a + ".max_rate");
    if (!dynamics_only) readChecked(r, prefix, static_cast<ActuatorLimitsParams*>(&c.actuator));
    // Delay and lag are optional_unnoted: absent = 0 without a note in the defaults list, so a
    // run without them reports exactly what it reported before them.
    readChecked(r, prefix, static_cast<ActuatorDynamicsParams*>(&c.dynamics));
  } else {
    r.noteDefault(prefix + ".actuator", "absent (no elevator limits)");
  }
  if (r.has(prefix + ".noise")) {
    const std::string nk = prefix + ".noise";
    c.noise.std = r.getVector(nk + ".std", want);
    for (Eigen::Index i = 0; i < c.noise.std.size(); ++i)
      if (r.usable(nk + ".std") && !(c.noise.std[i] >= 0.0))
        r.fail(nk + ".std", "must be >= 0, got " + formatNumber(c.noise.std[i]));
    readChecked(r, prefix, static_cast<MeasurementNoiseParams*>(&c.noise));
  } else {
    r.noteDefault(prefix + ".noise", "absent (no measurement noise)");
  }
  // (absent: still air, without a note)
  readChecked(r, prefix, static_cast<TurbulenceParams*>(&c.turbulence));
  // (absent: the B-747 defaults, checked, without a note: a run inside them reports nothing)
  readChecked(r, prefix, static_cast<FlightEnvelopeParams*>(&c.envelope));
  // (absent: the defaults, without a note: a linear run reports what it reported before)
  readChecked(r, prefix, static_cast<JsbsimParams*>(&c.jsbsim));
  // The operating point documents where A and B come from; its airspeed U is the V of the
  // turbulence filter, so required when turbulence is on.
  const std::string uk = prefix + ".operating_point.U";
  if (!r.has(uk) && c.turbulence.enabled)
    r.fail(uk, "required when plant.turbulence.enabled is true (the gust filter's airspeed V)");
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
  if (engine == PlantEngineKind::kJsbsim) validateJsbsim(r, prefix);
}

void PlantConfig::validateJsbsim(ParamReader& r, const std::string& prefix) const {
  // JSBSim integrates alpha and q; the package integrates e_I = int (alpha - r) dt. So the
  // state must be the paper's x = [e_I, alpha, q] with its integrator row, and the run starts
  // at the trim (alpha and q are perturbations from it).
  const std::string why = " with plant.engine jsbsim (x = [e_I, alpha, q], e_I_dot = alpha - r)";
  if (A.rows() != 3 || A.cols() != 3) {
    r.fail(prefix + ".A", "must be 3 x 3" + why);
    return;
  }
  if (r.usable(prefix + ".output_index") && output_index != 1)
    r.fail(prefix + ".output_index", "must be 1 (alpha)" + why);
  if (r.usable(prefix + ".A") && !(A(0, 0) == 0.0 && A(0, 1) == 1.0 && A(0, 2) == 0.0))
    r.fail(prefix + ".A", "its first row must be [0, 1, 0]" + why);
  if (r.usable(prefix + ".B") && B.size() == 3 && B[0] != 0.0)
    r.fail(prefix + ".B", "its first entry must be 0" + why);
  if (r.usable(prefix + ".B1r") && B1r.size() == 3 &&
      !(B1r[0] == -1.0 && B1r[1] == 0.0 && B1r[2] == 0.0))
    r.fail(prefix + ".B1r", "must be [-1, 0, 0]" + why);
  if (r.usable(prefix + ".x0") && x0.size() == 3 && !(x0[1] == 0.0 && x0[2] == 0.0))
    r.fail(prefix + ".x0",
           "alpha and q must start at 0 with plant.engine jsbsim (the run starts at the trim; "
           "e_I may start anywhere)");
}

double ActuatorLimits::apply(double u, double u_prev, double dt) const {
  return elevator().apply(u, u_prev, dt);
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
// without -mfma has no fused multiply-add to contract into; test_fast_paths compares the two paths
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
