#pragma once
/// \file sensitivity_tracker.hpp
/// \brief The sensitivity of the phase cost to theta_hat_I: the learning signal of pa_learn and
/// pa_learn_exact.

#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

/// \brief Sensitivity of the phase cost to theta_hat_I (eqs. E-der-exp, dot-ev-hth-der-exp),
/// S_dot = Pi S integrated alongside the controller.
class SensitivityTracker {
 public:
  SensitivityTracker() = default;
  SensitivityTracker(const Mat& Ar, const Vec& B, const Vec& PB, double gamma, int out);
  /// \brief Start a phase: S = [0; I], E = 0, g = 0.
  void start();
  /// \brief Add one sample's contribution over [t, t+dt): E += |e| dt, g += sign(e) S[out,:] dt,
  /// then S += dt Pi S. `theta_err` = theta - theta_hat (zero for the approximate gradient).
  void accumulate(double dt, const Vec& ev, const Vec& x, const Vec& theta_err);
  /// \brief Pi (2n x 2n) at the given signals; for tests and documentation, not the hot path.
  PiMat pi(const Vec& ev, const Vec& x, const Vec& theta_err) const;
  /// \brief A new adaptation gain from the next sample on (Controller::setTunables).
  void setGamma(double gamma) { gamma_ = gamma; }
  double cost() const { return E_; }
  const Vec& grad() const { return g_; }
  const SensMat& S() const { return S_; }

 private:
  Mat Ar_;
  Vec B_, PB_;
  double gamma_ = 0.0;
  int out_ = 1, n_ = 0;
  SensMat S_, Sdot_;
  double E_ = 0.0;
  Vec g_;
  /// \brief The rest of accumulate() for n = 3 (after E), without run-time sizes.
  void accumulate3(double dt, double sgn, const Vec& ev, const Vec& x, const Vec& theta_err);
};

}  // namespace preadaptive_mrac
