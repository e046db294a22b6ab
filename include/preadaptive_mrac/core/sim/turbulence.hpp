#pragma once
/// \file turbulence.hpp
/// \brief Dryden vertical turbulence (MIL-F-8785C / MIL-HDBK-1797): white noise through the
/// shaping filter H_w(s) = sigma_w sqrt(L_w/(pi V)) (1 + sqrt(3) (L_w/V) s) / (1 + (L_w/V) s)^2,
/// discretised exactly, with a random stream of its own.

#include <cstdint>

#include "preadaptive_mrac/core/sim/plant.hpp"

namespace preadaptive_mrac {

/// \brief The vertical gust w_g [m/s] at the samples t_k = k dt, held over each sample.
///
/// With tau = L_w / V the filter is, in controllable form, z1' = z2,
/// z2' = -z1/tau^2 - 2 z2/tau + n, w_g = (K/tau^2)(z1 + sqrt(3) tau z2), K = sigma_w
/// sqrt(tau/pi), driven by white noise n of intensity pi (one-sided spectral density 1), so
/// that the one-sided PSD of w_g is the Dryden Phi_w(omega) = sigma_w^2 (tau/pi)
/// (1 + 3 tau^2 omega^2)/(1 + tau^2 omega^2)^2, whose integral over [0, inf) is sigma_w^2.
/// Over a sample the state moves by the exact transition exp(F dt) (F has the double eigenvalue
/// -1/tau) plus a Gaussian vector with the exact covariance integral of the noise over the
/// sample: the samples have the continuous process's statistics for any dt. The state starts
/// in the stationary distribution, so w_g is stationary from t = 0.
class DrydenGust {
 public:
  /// \brief Airspeed V [m/s] > 0 (plant.operating_point.U), sample time dt [s] > 0.
  DrydenGust(const TurbulenceConfig& cfg, double airspeed, double dt);
  /// \brief The gust w_g [m/s] over the current sample (0 when inactive).
  double value() const { return w_; }
  /// \brief Move to the next sample.
  void advance();
  /// \brief Back to sample 0: the same sequence again.
  void reset();
  bool active() const { return active_; }
  /// \brief Dryden one-sided PSD Phi_w(omega) [(m/s)^2 / (rad/s)] at omega [rad/s].
  double psd(double omega) const;
  /// \brief The filter's time constant tau = L_w / V [s].
  double tau() const { return tau_; }

 private:
  void output();
  bool active_ = false;
  std::uint64_t seed_ = 0;
  double tau_ = 1.0, sigma_ = 0.0;
  double phi_[4] = {};   // exp(F dt), row-major
  double chol_[3] = {};  // lower Cholesky factor of the sample's noise covariance: l11, l21, l22
  double stat_[2] = {};  // standard deviations of z1, z2 in the stationary distribution
  double c_[2] = {};     // w_g = c . z
  double z_[2] = {};
  double w_ = 0.0;
  GaussianSource noise_;
};

}  // namespace preadaptive_mrac
