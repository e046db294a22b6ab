#include "preadaptive_mrac/core/controller/controller_config.hpp"

#include <cmath>

#include "preadaptive_mrac/core/schema/param_table.hpp"

namespace preadaptive_mrac {

ControllerConfig ControllerConfig::read(ParamReader& r, int n, const std::string& p) {
  ControllerConfig c;
  // The scalars of the table (params/controller.yaml), then what they cannot say.
  readScalars(r, p, &c);
  const std::string mode = r.getString(p + ".mode");
  if (r.has(p + ".mode")) c.mode = mode;
  c.Q = r.getMatrix(p + ".lqr.Q", n > 0 ? n : -1, n > 0 ? n : -1);
  c.theta_hat0 = r.getVector(p + ".adaptation.theta_hat0", n > 0 ? n : -1);
  const std::int64_t seed = r.getInt(p + ".preadaptation.seed");
  if (seed < 0) r.fail(p + ".preadaptation.seed", "must be >= 0, got " + std::to_string(seed));
  c.seed = static_cast<std::uint64_t>(seed < 0 ? 0 : seed);
  // Absent = measured, without a note in the defaults list: a run without the key reports
  // byte for byte what it reported before the key.
  const std::string fb = p + ".adaptation.elevator_feedback";
  if (r.has(fb)) {
    const std::string v = r.getString(fb);
    if (r.usable(fb) && !parseChoice(v, &c.elevator_feedback))
      r.fail(fb, std::string("expected one of ") + choiceNames(c.elevator_feedback) + ", got '" +
                     v + "'");
  }
  // The design model: each key optional, absent = the plant's (without a note, so a run
  // without the section reports byte for byte what it reported before it).
  if (r.has(p + ".model.A"))
    c.model.A = r.getMatrix(p + ".model.A", n > 0 ? n : -1, n > 0 ? n : -1);
  if (r.has(p + ".model.B")) c.model.B = r.getVector(p + ".model.B", n > 0 ? n : -1);
  if (r.has(p + ".model.B1r")) c.model.B1r = r.getVector(p + ".model.B1r", n > 0 ? n : -1);
  c.robust = RobustConfig::read(r, p + ".robust");
  c.l1 = L1Config::read(r, p + ".l1");
  c.validate(r, n, p);
  return c;
}

void ControllerConfig::validate(ParamReader& r, int n, const std::string& p) const {
  checkRanges(r, p, *this);
  // against c_e only when c_e itself was accepted: a bad c_e is reported once, by its own key
  if (r.usable(p + ".attention.hysteresis") && !r.failed(p + ".attention.c_e") &&
      !(hysteresis >= 0.0 && hysteresis < c_e))
    r.fail(p + ".attention.hysteresis",
           "must be in [0, c_e = " + formatNumber(c_e) + "), got " + formatNumber(hysteresis));
  if (r.has(p + ".projection") && projection && theta_hat0.size() > 0 &&
      r.usable(p + ".adaptation.theta_hat0") && theta_hat0.norm() > theta_max)
    r.fail(p + ".adaptation.theta_hat0",
           "lies outside Omega (norm " + formatNumber(theta_hat0.norm()) + " > theta_max)");
  const auto finite = [&](const std::string& key, const Eigen::MatrixXd& m) {
    if (m.size() > 0 && r.usable(key) && !m.allFinite())
      r.fail(key, "must be finite numbers (the controller designs on it)");
  };
  finite(p + ".model.A", model.A);
  finite(p + ".model.B", model.B);
  finite(p + ".model.B1r", model.B1r);
  if (model.B.size() > 0 && r.usable(p + ".model.B") && model.B.isZero(0.0))
    r.fail(p + ".model.B", "must not be all zero");
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

DesignModel DesignModelSection::over(DesignModel model) const {
  if (A.size() > 0) model.A = A;
  if (B.size() > 0) model.B = B;
  if (B1r.size() > 0) model.B1r = B1r;
  return model;
}

ControllerTunables ControllerTunables::of(const ControllerConfig& c) {
  ControllerTunables t;
  forEachTunable([](const char*, const char*, auto& to, const auto& from) { to = from; }, t, c);
  return t;
}

void ControllerTunables::applyTo(ControllerConfig* c) const {
  forEachTunable([](const char*, const char*, auto& to, const auto& from) { to = from; }, *c,
                 *this);
}

}  // namespace preadaptive_mrac
