#pragma once
/// \file l1_law.hpp
/// \brief L1 adaptive control of the matched uncertainty theta^T x (docs/research/l1.md): a state
/// predictor with the reference model's dynamics, the projection-based fast adaptation law of
/// Cao and Hovakimyan, and a low-pass filter C(s) = omega / (s + omega) on the adaptive term.
///
/// A part of its own: it knows the plant only through (A_r, B, b_ref, P) of the controller's
/// design (solvers.hpp) and never sees the true theta. Mode `l1` registers it as the adaptive
/// law (adaptive_law.hpp, mode_registry.cpp).

#include <memory>
#include <string>

#include "preadaptive_mrac/core/control/adaptive_law.hpp"
#include "preadaptive_mrac/core/control/l1/l1_config.hpp"
#include "preadaptive_mrac/core/solvers.hpp"
#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

/// \brief First-order low-pass C(s) = omega / (s + omega) with unit DC gain, discretised
/// exactly for an input held over each sample interval and known at its end:
/// y_k = a y_{k-1} + (1 - a) v_k, a = exp(-omega dt).
class LowPassFilter {
 public:
  LowPassFilter() = default;
  /// \brief omega [rad/s] > 0, dt [s] > 0.
  LowPassFilter(double omega, double dt);
  /// \brief y_k for input v_k, without moving the filter.
  double peek(double v) const { return a_ * y_ + (1.0 - a_) * v; }
  /// \brief Feed v_k; returns y_k.
  double update(double v) {
    y_ = peek(v);
    return y_;
  }
  double value() const { return y_; }
  double pole() const { return a_; }
  void reset(double y = 0.0) { y_ = y; }

 private:
  double a_ = 0.0;
  double y_ = 0.0;
};

/// \brief Smooth (Pomet-Praly) projection of an update direction y at theta onto
/// Omega = {|theta| <= theta_max}: the outward component of y is scaled down in the boundary
/// layer ((1 + eps) |theta|^2 > theta_max^2) and removed on the boundary.
void projectUpdate(const Vec& theta, double theta_max, double eps, Vec* y);

/// \brief L1 norm of G(s) = (sI - A_r)^-1 B (1 - C(s)), C(s) = omega / (s + omega): the largest
/// over the states i of the integral of |g_i(t)| dt, g the impulse response (RK4, step and
/// horizon chosen from omega and A_r's slowest pole). The L1 design condition (Cao and
/// Hovakimyan 2008) is l1NormOfG * L < 1 with L = max over Omega of |theta|_1
/// = sqrt(n) theta_max: C(s) must be wide enough for the uncertainty the projection allows.
double l1NormOfG(const Eigen::MatrixXd& Ar, const Eigen::VectorXd& B, double omega);

/// \brief The L1 adaptive law for x_dot = A_r x + B (u_ad + theta^T x) + b_ref r (the plant
/// under the baseline u_bl = -K x, A_r = A - B K):
///
///     predictor   xh_dot    = A_r xh + B (u_ad + theta_hat^T x) + b_ref r
///     adaptation  theta_hat_dot = Gamma Proj(theta_hat, -x (xt^T P B)),  xt = xh - x
///     control     u_ad      = C(s) [-theta_hat^T x + k0 r]
///
/// Per sample t_k (docs/research/l1.md, "Discretisation"): command() gives u_ad,k from x_k;
/// advance() then moves the filter, the predictor (RK4 with its input held, the reference model's
/// discretisation) and theta_hat (forward Euler, projected, clamped to Omega) to t_{k+1}.
/// Allocation-free after construction.
class L1Law : public AdaptiveLaw {
 public:
  /// \brief `design` from designController (K, A_r, P); B the plant's input vector; b_ref the
  /// reference input vector (B1r + k0 B); k0 the feed-forward gain of r; dt [s] the sample
  /// time; theta_hat0 the initial estimate (projected into Omega); x0 the initial state.
  L1Law(const ControllerDesign& design, const Vec& B, const Vec& b_ref, double k0,
        const L1Config& cfg, double dt, const Vec& theta_hat0, const Vec& x0);

  // The adaptive-law seam (adaptive_law.hpp).
  std::unique_ptr<AdaptiveLaw> clone() const override { return std::make_unique<L1Law>(*this); }
  /// \brief Back to the initial predictor state, estimate and filter.
  void reset() override;
  const Vec& estimate() const override { return theta_hat_; }
  Vec* mutableEstimate() override { return &theta_hat_; }
  /// \brief An estimate set from outside (a preadaptation reset) is projected into Omega.
  void constrain() override;
  double command(const LawInput& in) const override { return command(*in.x, in.r); }
  /// \brief advance() below with the law's own command as the adaptive part applied, less what
  /// the known limits took off it when the controller hedges (LawInput::limited).
  void advance(const LawInput& in, bool adapt) override {
    advance(*in.x, in.r, command(*in.x, in.r) + in.limited, adapt);
  }

  /// \brief The adaptive command at sample k from the measured x_k and r_k [rad]: the filter
  /// fed -theta_hat_k^T x_k + k0 r_k. Does not move the filter; advance() does.
  double command(const Vec& x, double r) const;
  /// \brief Advance filter, predictor and estimate to t_{k+1}. `u_ad_applied` [rad] is the
  /// adaptive part the plant received over the sample (the command, or less when the elevator
  /// was limited: u_applied + K x). `adapt` false freezes theta_hat over this sample.
  void advance(const Vec& x, double r, double u_ad_applied, bool adapt = true);

  const Vec& thetaHat() const { return theta_hat_; }
  /// \brief Predictor state xh at the current sample.
  const Vec& xHat() const { return x_hat_; }
  /// \brief Prediction error xt = xh - x of the last advanced sample.
  const Vec& predictionError() const { return x_tilde_; }
  /// \brief theta_hat^T x of the last advanced sample: the estimate of the matched uncertainty.
  double sigmaHat() const { return sigma_hat_; }
  const LowPassFilter& filter() const { return filter_; }
  const L1Config& config() const { return cfg_; }

 private:
  L1Config cfg_;
  double dt_ = 0.0, k0_ = 0.0;
  Vec PB_;
  Mat Phi_;    // RK4 transition of the predictor over dt
  Vec Gam_b_;  // RK4 input vector of B over dt
  Vec Gam_r_;  // RK4 input vector of b_ref over dt
  Vec x_hat0_, theta_hat0_;
  Vec x_hat_, theta_hat_, x_tilde_, upd_;
  double sigma_hat_ = 0.0;
  LowPassFilter filter_;
};

struct ModeContext;
/// \brief The registry's factory of L1Law (mode `l1`): the controller's design, B, B1r + k0 B,
/// `controller.l1`, the sample time, theta_hat0 and the plant's x0.
std::unique_ptr<AdaptiveLaw> makeL1Law(const ModeContext& m);

}  // namespace preadaptive_mrac
