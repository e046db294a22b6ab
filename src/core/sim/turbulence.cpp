#include "preadaptive_mrac/core/sim/turbulence.hpp"

#include <cmath>
#include <stdexcept>

namespace preadaptive_mrac {

namespace {
constexpr double kPi = 3.14159265358979323846;

// The lower incomplete gamma integral of t^n e^{-t} over [0, x], for n = 0, 1, 2. For small x
// the closed form n! (1 - e^{-x} sum_{k<=n} x^k/k!) cancels; the series
// n! e^{-x} sum_{k>n} x^k/k! does not.
double gammaInt(int n, double x) {
  double fact = 1.0;
  for (int k = 2; k <= n; ++k) fact *= k;
  if (x > 2.0) {
    double sum = 0.0, term = 1.0;
    for (int k = 0; k <= n; ++k) {
      sum += term;
      term *= x / (k + 1);
    }
    return fact * (1.0 - std::exp(-x) * sum);
  }
  double term = 1.0;
  for (int k = 1; k <= n + 1; ++k) term *= x / k;  // x^{n+1}/(n+1)!
  double sum = 0.0;
  for (int k = n + 1; k < n + 60 && term > 1e-18 * sum; ++k) {
    sum += term;
    term *= x / (k + 1);
  }
  return fact * std::exp(-x) * sum;
}
}  // namespace

DrydenGust::DrydenGust(const TurbulenceConfig& cfg, double airspeed, double dt)
    : active_(cfg.active()), seed_(cfg.seed), noise_(cfg.seed) {
  if (!active_) return;
  if (!(airspeed > 0.0) || !(cfg.length_scale > 0.0) || !(dt > 0.0) || !(cfg.sigma_w >= 0.0))
    throw std::invalid_argument("DrydenGust: need V > 0, L_w > 0, dt > 0, sigma_w >= 0");
  tau_ = cfg.length_scale / airspeed;
  sigma_ = cfg.sigma_w;
  const double a = 1.0 / tau_, q = kPi;
  // F = [[0, 1], [-a^2, -2a]] has the double eigenvalue -a, so (F + a I)^2 = 0 and
  // exp(F h) = e^{-a h} (I + (F + a I) h).
  const double e = std::exp(-a * dt);
  phi_[0] = e * (1.0 + a * dt);
  phi_[1] = e * dt;
  phi_[2] = -e * a * a * dt;
  phi_[3] = e * (1.0 - a * dt);
  // exp(F s) [0, 1]^T = e^{-a s} [s, 1 - a s]; the covariance of a sample's noise is
  // q times the integral over [0, dt] of its outer product: I_n = int s^n e^{-2 a s} ds.
  const double b = 2.0 * a, x = b * dt;
  const double i0 = gammaInt(0, x) / b, i1 = gammaInt(1, x) / (b * b),
               i2 = gammaInt(2, x) / (b * b * b);
  const double q11 = q * i2, q12 = q * (i1 - a * i2), q22 = q * (i0 - 2.0 * a * i1 + a * a * i2);
  chol_[0] = std::sqrt(q11);
  chol_[1] = q12 / chol_[0];
  chol_[2] = std::sqrt(std::max(0.0, q22 - chol_[1] * chol_[1]));
  // Stationary covariance of z'' + 2a z' + a^2 z = n: diag(q/(4a^3), q/(4a)).
  stat_[0] = std::sqrt(q / (4.0 * a * a * a));
  stat_[1] = std::sqrt(q / (4.0 * a));
  const double k = sigma_ * std::sqrt(tau_ / kPi);
  c_[0] = k / (tau_ * tau_);
  c_[1] = k * std::sqrt(3.0) / tau_;
  reset();
}

void DrydenGust::reset() {
  if (!active_) return;
  noise_.reseed(seed_);
  z_[0] = stat_[0] * noise_.next();
  z_[1] = stat_[1] * noise_.next();
  output();
}

void DrydenGust::output() { w_ = c_[0] * z_[0] + c_[1] * z_[1]; }

void DrydenGust::advance() {
  if (!active_) return;
  const double n1 = noise_.next(), n2 = noise_.next();
  const double z0 = phi_[0] * z_[0] + phi_[1] * z_[1] + chol_[0] * n1;
  const double z1 = phi_[2] * z_[0] + phi_[3] * z_[1] + chol_[1] * n1 + chol_[2] * n2;
  z_[0] = z0;
  z_[1] = z1;
  output();
}

double DrydenGust::psd(double omega) const {
  const double y = tau_ * tau_ * omega * omega;
  return sigma_ * sigma_ * (tau_ / kPi) * (1.0 + 3.0 * y) / ((1.0 + y) * (1.0 + y));
}

}  // namespace preadaptive_mrac
