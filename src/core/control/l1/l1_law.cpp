#include "preadaptive_mrac/core/control/l1/l1_law.hpp"

#include <cmath>

#include "preadaptive_mrac/core/control/design_model.hpp"
#include "preadaptive_mrac/core/control/mode_context.hpp"
#include "preadaptive_mrac/core/small_ops.hpp"
#include "preadaptive_mrac/core/solvers.hpp"
#include "preadaptive_mrac/params/controller_params.hpp"

namespace preadaptive_mrac {

LowPassFilter::LowPassFilter(double omega, double dt) : a_(std::exp(-omega * dt)) {}

void projectUpdate(const Vec& theta, double theta_max, double eps, Vec* y) {
  // f(theta) = ((1 + eps) |theta|^2 - theta_max^2) / (eps theta_max^2): f <= 0 inside the inner
  // ball, f = 1 on |theta| = theta_max. Outward components of y are scaled down by f there.
  const double tm2 = theta_max * theta_max;
  const double th2 = theta.squaredNorm();
  const double f = ((1.0 + eps) * th2 - tm2) / (eps * tm2);
  if (f <= 0.0) return;
  const double grad_dot_y = theta.dot(*y);  // grad f is parallel to theta
  if (grad_dot_y <= 0.0) return;
  *y -= (std::min(f, 1.0) * grad_dot_y / th2) * theta;
}

double l1NormOfG(const Eigen::MatrixXd& Ar, const Eigen::VectorXd& B, double omega) {
  // Impulse response of x' = A_r x + B (u - omega z), z' = -omega z + u: x(0+) = B, z(0+) = 1,
  // then free. Integrated until the slowest of A_r's poles and the filter's has decayed by
  // e^-40, with a step resolving both.
  const int n = static_cast<int>(B.size());
  const double slow = std::min(-spectralAbscissa(Ar), omega);
  const double fast = std::max(Ar.norm(), omega);
  const double h = std::min(1e-3, 0.1 / fast);
  const long steps = static_cast<long>(40.0 / slow / h) + 1;
  Eigen::MatrixXd F = Eigen::MatrixXd::Zero(n + 1, n + 1);
  F.topLeftCorner(n, n) = Ar;
  F.topRightCorner(n, 1) = -omega * B;
  F(n, n) = -omega;
  const Eigen::MatrixXd Phi = rk4Hold(F, h).Phi;  // free: no input
  Eigen::VectorXd s(n + 1), next(n + 1);
  s << B, 1.0;
  Eigen::VectorXd integral = Eigen::VectorXd::Zero(n);
  for (long k = 0; k < steps; ++k) {  // trapezoids of |x_i|
    next = Phi * s;
    integral += 0.5 * h * (s.head(n).cwiseAbs() + next.head(n).cwiseAbs());
    s = next;
  }
  return integral.maxCoeff();
}

namespace {
void clampInto(Vec* theta, double radius) {
  const double nrm = theta->norm();
  if (nrm > radius) *theta *= radius / nrm;
}
}  // namespace

L1Law::L1Law(const ControllerDesign& design, const Vec& B, const Vec& b_ref, double k0,
             const L1Config& cfg, double dt, const Vec& theta_hat0, const Vec& x0)
    : cfg_(cfg), dt_(dt), k0_(k0), filter_(cfg.bandwidth, dt) {
  const int n = static_cast<int>(B.size());
  PB_ = design.P * B;
  // The predictor xh' = A_r xh + w, RK4 with w held over the sample, as the controller's
  // reference model (so predictor and reference model are discretised alike).
  const Rk4Hold hold = rk4Hold(design.Ar, dt);
  Phi_ = hold.Phi;
  Gam_b_ = hold.G * Eigen::VectorXd(B);
  Gam_r_ = hold.G * Eigen::VectorXd(b_ref);
  x_hat0_ = x0;
  theta_hat0_ = theta_hat0;
  clampInto(&theta_hat0_, cfg_.theta_max);
  x_tilde_.setZero(n);
  upd_.setZero(n);
  reset();
}

void L1Law::reset() {
  x_hat_ = x_hat0_;
  theta_hat_ = theta_hat0_;
  x_tilde_.setZero(x_hat0_.size());
  sigma_hat_ = 0.0;
  filter_.reset();
}

void L1Law::constrain() { clampInto(&theta_hat_, cfg_.theta_max); }

double L1Law::command(const Vec& x, double r) const {
  return filter_.peek(-dotOf(theta_hat_, x) + k0_ * r);
}

void L1Law::advance(const Vec& x, double r, double u_ad_applied, bool adapt) {
  differenceTo(x_hat_, x, &x_tilde_);
  sigma_hat_ = dotOf(theta_hat_, x);
  filter_.update(-sigma_hat_ + k0_ * r);  // u_ad,k as command() gave it
  // Predictor next, with the estimate the sample was predicted with (theta_hat_k).
  lazyProductPlus(Phi_, x_hat_, Gam_r_, r, &x_hat_);
  addScaled(u_ad_applied + sigma_hat_, Gam_b_, &x_hat_);
  if (!adapt) return;
  // theta_hat_dot = Gamma Proj(theta_hat, -x (xt^T P B)), forward Euler with the sampled x;
  // the Euler step can overshoot the boundary layer by O(dt), hence the clamp.
  scaledTo(-cfg_.gamma * dotOf(x_tilde_, PB_), x, &upd_);
  projectUpdate(theta_hat_, cfg_.theta_max, cfg_.projection_epsilon, &upd_);
  addScaled(dt_, upd_, &theta_hat_);
  clampInto(&theta_hat_, cfg_.theta_max);
}

std::unique_ptr<AdaptiveLaw> makeL1Law(const ModeContext& m) {
  const ControllerParams& c = *m.cfg;
  const Vec b_ref = m.model->B1r + c.k0 * *m.B;
  return std::make_unique<L1Law>(*m.design, *m.B, b_ref, c.k0, *m.l1, c.sample_time, c.theta_hat0,
                                 m.model->x0);
}

}  // namespace preadaptive_mrac
