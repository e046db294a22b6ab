#include "preadaptive_mrac/core/controller_config.hpp"

#include <cmath>

#include "preadaptive_mrac/core/mode_registry.hpp"
#include "preadaptive_mrac/core/network.hpp"
#include "preadaptive_mrac/core/params.hpp"

namespace preadaptive_mrac {

ControllerConfig ControllerConfig::read(ParamReader& r, int n, const std::string& p) {
  ControllerConfig c;
  const std::string mode = r.getString(p + ".mode");
  if (r.has(p + ".mode")) {
    if (findMode(mode) != nullptr)
      c.mode = mode;
    else
      r.fail(p + ".mode", "expected one of " + modeNames(", ") + ", got '" + mode + "'");
  }
  c.sample_time = r.getDouble(p + ".sample_time");
  c.Q = r.getMatrix(p + ".lqr.Q", n > 0 ? n : -1, n > 0 ? n : -1);
  c.R = r.getDouble(p + ".lqr.R");
  c.k0 = r.getDouble(p + ".reference_model.k0");
  c.gamma = r.getDouble(p + ".adaptation.gamma");
  c.theta_hat0 = r.getVector(p + ".adaptation.theta_hat0", n > 0 ? n : -1);
  c.tau = r.getDouble(p + ".velocity_estimator.tau");
  c.c_e = r.getDouble(p + ".attention.c_e");
  c.c_ed = r.getDouble(p + ".attention.c_ed");
  c.hidden = static_cast<int>(r.getInt(p + ".preadaptation.hidden"));
  c.init_scale = r.getDouble(p + ".preadaptation.init_scale");
  const std::int64_t seed = r.getInt(p + ".preadaptation.seed");
  if (seed < 0) r.fail(p + ".preadaptation.seed", "must be >= 0, got " + std::to_string(seed));
  c.seed = static_cast<std::uint64_t>(seed < 0 ? 0 : seed);
  c.gamma_pa = r.getDouble(p + ".preadaptation.gamma_pa");
  // Options beyond the paper: optional, and their defaults reproduce the paper.
  c.confirm_samples = static_cast<int>(r.getInt(p + ".attention.confirm_samples", 0));
  c.hysteresis = r.getDouble(p + ".attention.hysteresis", 0.0);
  c.freeze_when_saturated = r.getBool(p + ".adaptation.freeze_when_saturated", true);
  // Absent = measured, without a note in the defaults list: a run without the key reports
  // byte for byte what it reported before the key.
  const std::string fb = p + ".adaptation.elevator_feedback";
  if (r.has(fb)) {
    const std::string v = r.getString(fb);
    if (v == "commanded")
      c.elevator_feedback = ElevatorFeedback::kCommanded;
    else if (v != "measured" && r.usable(fb))
      r.fail(fb, "expected one of measured, commanded, got '" + v + "'");
  }
  if (r.has(p + ".projection")) {
    c.projection = r.getBool(p + ".projection.enabled");
    c.theta_max = r.getDouble(p + ".projection.theta_max");
    c.projection_epsilon = r.getDouble(p + ".projection.epsilon");
  } else {
    r.noteDefault(p + ".projection", "absent (no projection)");
  }
  c.robust = RobustConfig::read(r, p + ".robust");
  c.l1 = L1Config::read(r, p + ".l1");
  c.validate(r, n, p);
  return c;
}

void ControllerConfig::validate(ParamReader& r, int n, const std::string& p) const {
  auto positive = [&](const std::string& key, double v) {
    if (r.usable(key) && !(v > 0.0)) r.fail(key, "must be > 0, got " + formatNumber(v));
  };
  positive(p + ".sample_time", sample_time);
  positive(p + ".lqr.R", R);
  positive(p + ".adaptation.gamma", gamma);
  positive(p + ".attention.c_e", c_e);
  positive(p + ".attention.c_ed", c_ed);
  positive(p + ".preadaptation.gamma_pa", gamma_pa);
  if (r.usable(p + ".velocity_estimator.tau") && !(tau >= 0.0))
    r.fail(p + ".velocity_estimator.tau", "must be >= 0, got " + formatNumber(tau));
  if (r.usable(p + ".preadaptation.init_scale") && !(init_scale >= 0.0))
    r.fail(p + ".preadaptation.init_scale", "must be >= 0, got " + formatNumber(init_scale));
  if (r.usable(p + ".preadaptation.hidden") && (hidden < 1 || hidden > kMaxHidden))
    r.fail(p + ".preadaptation.hidden",
           "must be in [1, " + std::to_string(kMaxHidden) + "], got " + std::to_string(hidden));
  if (r.usable(p + ".attention.confirm_samples") && confirm_samples < 0)
    r.fail(p + ".attention.confirm_samples",
           "must be >= 0, got " + std::to_string(confirm_samples));
  if (r.usable(p + ".attention.hysteresis") && !(hysteresis >= 0.0 && hysteresis < c_e))
    r.fail(p + ".attention.hysteresis",
           "must be in [0, c_e = " + formatNumber(c_e) + "), got " + formatNumber(hysteresis));
  if (r.has(p + ".projection")) {
    positive(p + ".projection.theta_max", theta_max);
    if (r.usable(p + ".projection.epsilon") &&
        !(projection_epsilon > 0.0 && projection_epsilon <= 1.0))
      r.fail(p + ".projection.epsilon",
             "must be in (0, 1], got " + formatNumber(projection_epsilon));
    if (projection && theta_hat0.size() > 0 && r.usable(p + ".adaptation.theta_hat0") &&
        theta_hat0.norm() > theta_max)
      r.fail(p + ".adaptation.theta_hat0",
             "lies outside Omega (norm " + formatNumber(theta_hat0.norm()) + " > theta_max)");
  }
  if (r.has(p + ".robust")) robust.validate(r, p + ".robust");
  if (r.has(p + ".l1")) l1.validate(r, p + ".l1", sample_time);
  if (n > 0 && Q.rows() == n && Q.cols() == n && r.usable(p + ".lqr.Q")) {
    if ((Q - Q.transpose()).norm() > 1e-12 * std::max(1.0, Q.norm()))
      r.fail(p + ".lqr.Q", "must be symmetric");
    else if (Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Q).eigenvalues().minCoeff() <
             -1e-12 * std::max(1.0, Q.norm()))
      r.fail(p + ".lqr.Q", "must be positive semi-definite");
  }
}

namespace {
// ControllerConfig and ControllerTunables name the tunables alike: one copy serves both ways.
template <class From, class To>
void copyTunables(const From& f, To* t) {
  t->c_e = f.c_e;
  t->c_ed = f.c_ed;
  t->confirm_samples = f.confirm_samples;
  t->hysteresis = f.hysteresis;
  t->gamma = f.gamma;
  t->gamma_pa = f.gamma_pa;
  t->projection = f.projection;
  t->theta_max = f.theta_max;
  t->projection_epsilon = f.projection_epsilon;
  t->robust = f.robust;
}
}  // namespace

ControllerTunables ControllerTunables::of(const ControllerConfig& c) {
  ControllerTunables t;
  copyTunables(c, &t);
  return t;
}

void ControllerTunables::applyTo(ControllerConfig* c) const { copyTunables(*this, c); }

}  // namespace preadaptive_mrac
