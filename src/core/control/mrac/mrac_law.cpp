#include "preadaptive_mrac/core/control/mrac/mrac_law.hpp"

#include <algorithm>

#include "preadaptive_mrac/core/control/mode_context.hpp"
#include "preadaptive_mrac/core/small_ops.hpp"
#include "preadaptive_mrac/params/controller_params.hpp"

namespace preadaptive_mrac {

MracLaw::MracLaw(const ControllerParams& cfg, const Vec& PB)
    : PB_(PB),
      theta_hat0_(cfg.theta_hat0),
      dt_(cfg.sample_time),
      k0_(cfg.k0),
      gamma_(cfg.gamma),
      projection_(cfg.projection),
      theta_max_(cfg.theta_max),
      epsilon_(cfg.projection_epsilon) {
  upd_.setZero(PB.size());
  reset();
}

void MracLaw::reset() { theta_hat_ = theta_hat0_; }

void MracLaw::constrain() {
  if (projection_) clampToBall(&theta_hat_, theta_max_);
}

void MracLaw::advanceProjected() {
  project(theta_hat_, &upd_);
  addScaled(dt_, upd_, &theta_hat_);
  clampToBall(&theta_hat_, theta_max_);  // the Euler step can overshoot the boundary layer by O(dt)
}

void MracLaw::setTunables(const ControllerParams& cfg) {
  gamma_ = cfg.gamma;
  projection_ = cfg.projection;
  theta_max_ = cfg.theta_max;
  epsilon_ = cfg.projection_epsilon;
  // Projection switched on: the estimate starts inside Omega, as at a reset.
  constrain();
}

void MracLaw::project(const Vec& theta, Vec* y) const {
  // f(theta) = ((1 + eps) |theta|^2 - theta_max^2) / (eps theta_max^2): f <= 0 inside the inner
  // ball, f = 1 on |theta| = theta_max. Outward components of y are scaled down by f there.
  const double tm2 = theta_max_ * theta_max_;
  const double eps = epsilon_;
  const double f = ((1.0 + eps) * theta.squaredNorm() - tm2) / (eps * tm2);
  if (f <= 0.0) return;
  const double grad_dot_y = theta.dot(*y);  // grad f is parallel to theta
  if (grad_dot_y <= 0.0) return;
  const double th2 = theta.squaredNorm();
  *y -= (std::min(f, 1.0) * grad_dot_y / th2) * theta;
}

std::unique_ptr<AdaptiveLaw> makeMracLaw(const ModeContext& m) {
  return std::make_unique<MracLaw>(*m.cfg, *m.PB);
}

}  // namespace preadaptive_mrac
