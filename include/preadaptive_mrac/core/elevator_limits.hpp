#pragma once
/// \file elevator_limits.hpp
/// \brief The elevator's travel and rate limits and the one rule that applies them: below
/// both the simulator (which applies plant.actuator) and the controller (which knows them).

#include <algorithm>

namespace preadaptive_mrac {

/// \brief Elevator magnitude and rate limits: |u| <= max_deflection [rad],
/// |du/dt| <= max_rate [rad/s]; none when not enabled.
struct ElevatorLimits {
  bool enabled = false;
  double max_deflection = 0.0;  ///< [rad]
  double max_rate = 0.0;        ///< [rad/s]

  /// \brief The deflection the actuator reaches over one step of dt [s] when commanded u
  /// from u_prev [rad]: rate-limited, then clamped. The identity when disabled.
  double apply(double u, double u_prev, double dt) const {
    if (!enabled) return u;
    const double step = max_rate * dt;
    const double v = std::min(std::max(u, u_prev - step), u_prev + step);
    return std::min(std::max(v, -max_deflection), max_deflection);
  }
};

}  // namespace preadaptive_mrac
