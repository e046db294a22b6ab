#include "preadaptive_mrac/core/control/attention_thresholds.hpp"

#include <algorithm>
#include <cmath>

namespace preadaptive_mrac {

DerivedAttention deriveAttentionThresholds(const Eigen::MatrixXd& Ar, const Eigen::VectorXd& B,
                                           const Eigen::VectorXd& b_ref, int out, double r,
                                           double noise_std, double dt) {
  DerivedAttention d;
  const Eigen::VectorXd x_ref = -Ar.partialPivLu().solve(b_ref * r);
  d.disturbance = std::abs(x_ref.sum());
  // The step response of e_dot = A_r e + B d, RK4 with d held (as the reference model is
  // stepped), over ten of the slowest time constants of A_r.
  const double slowest = Ar.eigenvalues().real().cwiseAbs().minCoeff();
  const double horizon = std::min(10.0 / std::max(slowest, 1e-3), 600.0);
  const Eigen::Index n = Ar.rows();
  const Eigen::MatrixXd M = Ar * dt, I = Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd M2 = M * M, M3 = M2 * M, M4 = M3 * M;
  const Eigen::MatrixXd Phi = I + M + M2 / 2.0 + M3 / 6.0 + M4 / 24.0;
  const Eigen::VectorXd Gam = dt * (I + M / 2.0 + M2 / 6.0 + M3 / 24.0) * B * d.disturbance;
  Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
  const long steps = static_cast<long>(std::ceil(horizon / dt));
  for (long k = 0; k < steps; ++k) {
    e = Phi * e + Gam;
    d.error_peak = std::max(d.error_peak, std::abs(e[out]));
  }
  d.noise_floor = kAttentionNoiseFactor * noise_std;
  d.c_e = std::max(kAttentionErrorFraction * d.error_peak, d.noise_floor);
  d.c_ed = kAttentionRateRatio * d.c_e;
  return d;
}

}  // namespace preadaptive_mrac
