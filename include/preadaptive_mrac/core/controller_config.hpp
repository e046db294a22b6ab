#pragma once
/// \file controller_config.hpp
/// \brief The controller's parameters (key `controller`) and the subset tunable at run time.

#include <cstdint>
#include <optional>
#include <string>

#include "preadaptive_mrac/core/l1_law.hpp"
#include "preadaptive_mrac/core/robust_config.hpp"
#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

class ParamReader;

/// \brief The elevator deflection a sample reports as applied over the previous step, which
/// pa_robust's identification integrates: `measured` (the plant's surface position after delay,
/// lag and limits, when the plant reports it) or `commanded` (the controller's own last command,
/// for a controller without a surface-position sensor).
enum class ElevatorFeedback { kMeasured, kCommanded };

/// \brief Controller parameters (key `controller`); see config/controller/default.yaml.
struct ControllerConfig {
  std::string mode = "pa_learn";      ///< a registered mode (mode_registry.hpp)
  double sample_time = 0.001;         ///< controller period dt [s]
  Eigen::MatrixXd Q;                  ///< LQR state weight (n x n, symmetric >= 0)
  double R = 1.0;                     ///< LQR input weight (> 0)
  double k0 = 0.0;                    ///< feed-forward gain of r (B2r = k0 B)
  double gamma = 10.0;                ///< adaptation gain
  Eigen::VectorXd theta_hat0;         ///< initial estimate (n)
  double tau = 0.01;                  ///< velocity-estimator time constant [s]
  double c_e = 0.005;                 ///< attention error threshold [rad]
  double c_ed = 0.02;                 ///< attention rate threshold [rad/s]
  int hidden = 3;                     ///< hidden neurons
  double init_scale = 1.0;            ///< initial weights uniform in [-init_scale, init_scale]
  std::uint64_t seed = 1;             ///< seed of the initial weights
  double gamma_pa = 10.0;             ///< learning rate of the preadaptation learner
  int confirm_samples = 0;            ///< attention debounce: crossings must hold this many samples
  double hysteresis = 0.0;            ///< attention: recovery threshold is c_e - hysteresis [rad]
  bool freeze_when_saturated = true;  ///< no adaptation while the elevator is at a limit
  /// controller.adaptation.elevator_feedback: what the identification takes as applied
  ElevatorFeedback elevator_feedback = ElevatorFeedback::kMeasured;
  bool projection = false;          ///< smooth projection of theta_hat onto ||theta|| <= theta_max
  double theta_max = 25.0;          ///< radius of Omega (used once projection is enabled)
  double projection_epsilon = 0.1;  ///< width of the projection's boundary layer (> 0)
  RobustConfig robust;              ///< pa_robust (optional section; defaults documented)
  L1Config l1;                      ///< mode l1 (optional section `controller.l1`; docs/l1.md)

  /// \brief Read the `controller` section for a plant of n states; problems go to the reader.
  static ControllerConfig read(ParamReader& r, int n, const std::string& prefix = "controller");
  /// \brief Every problem with the values (signs, sizes, finiteness) into the reader.
  void validate(ParamReader& r, int n, const std::string& prefix = "controller") const;
};

/// \brief The parameters that may change while the controller runs (dynamic_reconfigure):
/// attention thresholds, adaptation and learning gains, projection and pa_robust's parameters.
/// Controller::setTunables queues them; they take effect at the start of the next step().
struct ControllerTunables {
  double c_e = 0.005;               ///< controller.attention.c_e [rad]
  double c_ed = 0.02;               ///< controller.attention.c_ed [rad/s]
  int confirm_samples = 0;          ///< controller.attention.confirm_samples
  double hysteresis = 0.0;          ///< controller.attention.hysteresis [rad]
  double gamma = 10.0;              ///< controller.adaptation.gamma
  double gamma_pa = 10.0;           ///< controller.preadaptation.gamma_pa
  bool projection = false;          ///< controller.projection.enabled
  double theta_max = 25.0;          ///< controller.projection.theta_max
  double projection_epsilon = 0.1;  ///< controller.projection.epsilon
  RobustConfig robust;              ///< controller.robust.*

  /// \brief The tunables of a configuration.
  static ControllerTunables of(const ControllerConfig& c);
  /// \brief Write these values into a configuration.
  void applyTo(ControllerConfig* c) const;
};

}  // namespace preadaptive_mrac
