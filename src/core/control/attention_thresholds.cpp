#include "preadaptive_mrac/core/control/attention_thresholds.hpp"

#include <algorithm>
#include <cmath>

#include "preadaptive_mrac/core/solvers.hpp"

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
  const Rk4Hold hold = rk4Hold(Ar, dt);
  const Eigen::VectorXd GB = hold.G * B;
  const Eigen::VectorXd Gam = GB * d.disturbance;
  Eigen::VectorXd e = Eigen::VectorXd::Zero(Ar.rows());
  const long steps = static_cast<long>(std::ceil(horizon / dt));
  for (long k = 0; k < steps; ++k) {
    e = hold.Phi * e + Gam;
    d.error_peak = std::max(d.error_peak, std::abs(e[out]));
  }
  d.noise_floor = kAttentionNoiseFactor * noise_std;
  d.c_e = std::max(kAttentionErrorFraction * d.error_peak, d.noise_floor);
  d.c_ed = kAttentionRateRatio * d.c_e;
  return d;
}

}  // namespace preadaptive_mrac
