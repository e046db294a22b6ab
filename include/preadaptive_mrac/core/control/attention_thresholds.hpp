#pragma once
/// \file attention_thresholds.hpp
/// \brief The attention thresholds c_e and c_ed derived from the design model and the
/// measurement noise (`controller.attention.thresholds: derived`), so they fit the aircraft as K
/// and P do.

#include <Eigen/Dense>

namespace preadaptive_mrac {

/// \brief The derived thresholds and the quantities they come from.
struct DerivedAttention {
  double c_e = 0.0;          ///< |e| threshold [rad]
  double c_ed = 0.0;         ///< |e_dot| threshold [rad/s]
  double disturbance = 0.0;  ///< d = |1^T x_ref|, the elevator a unit regime adds [rad]
  double error_peak = 0.0;   ///< peak |e| of the reference-model loop after a step d [rad]
  double noise_floor = 0.0;  ///< kAttentionNoiseFactor x the output's noise std [rad]
};

/// c_e is this fraction of error_peak (one eighth: 4.9 mrad on the B-747, the paper's 5 mrad).
constexpr double kAttentionErrorFraction = 0.125;
/// c_ed = c_e x this rate [1/s]: the paper's ratio c_ed / c_e = 0.02 / 0.005.
constexpr double kAttentionRateRatio = 4.0;
/// c_e is at least this many standard deviations of the noise on the output.
constexpr double kAttentionNoiseFactor = 5.0;

/// \brief c_e and c_ed for the error e = x[out] - x_r[out] of the loop e_dot = A_r e + B d.
///
/// A unit regime is a change of theta by a vector of ones (the paper's regimes are multiples
/// of it) while the aircraft holds the reference model's steady state for the command `r`,
/// x_ref = -A_r^{-1} b_ref r: it adds d = |1^T x_ref| to the elevator. The loop's error after a
/// step d (no adaptation) peaks at error_peak; c_e = max(kAttentionErrorFraction error_peak,
/// kAttentionNoiseFactor noise_std), c_ed = kAttentionRateRatio c_e.
/// \param Ar reference model A_r = A - B K (Hurwitz)
/// \param B elevator input of the design model
/// \param b_ref command input of the reference model (B1r + k0 B)
/// \param out index of the tracked output
/// \param r the command the thresholds are sized for [rad]
/// \param noise_std standard deviation of the noise on x[out] [rad]
/// \param dt the controller's sample time [s] (the step of the simulated response)
DerivedAttention deriveAttentionThresholds(const Eigen::MatrixXd& Ar, const Eigen::VectorXd& B,
                                           const Eigen::VectorXd& b_ref, int out, double r,
                                           double noise_std, double dt);

}  // namespace preadaptive_mrac
