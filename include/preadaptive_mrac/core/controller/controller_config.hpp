#pragma once
/// \file controller_config.hpp
/// \brief The controller's parameters (key `controller`) and the subset tunable at run time.
/// The values, defaults, docs, ranges and the tunables are declared once, in
/// params/controller.yaml and its parts' tables (params/robust.yaml, params/l1.yaml), and
/// generated into ControllerParams, RobustParams, L1Params and ControllerTunableParams
/// (preadaptive_mrac/params/*_params.hpp); what no table row can say is checked here.

#include <Eigen/Dense>
#include <string>

#include "preadaptive_mrac/core/control/design_model.hpp"
#include "preadaptive_mrac/core/control/l1/l1_config.hpp"
#include "preadaptive_mrac/core/robust/robust_config.hpp"
#include "preadaptive_mrac/core/types.hpp"
#include "preadaptive_mrac/params/controller_params.hpp"

namespace preadaptive_mrac {

class ParamReader;

/// \brief The controller's own parts of its design model (optional section
/// `controller.model`): each part left out (size 0 here) is the plant's.
struct DesignModelSection {
  Eigen::MatrixXd A;    ///< `controller.model.A` (empty: `plant.A`)
  Eigen::VectorXd B;    ///< `controller.model.B` (empty: `plant.B`)
  Eigen::VectorXd B1r;  ///< `controller.model.B1r` (empty: `plant.B1r`)
  bool empty() const { return A.size() == 0 && B.size() == 0 && B1r.size() == 0; }
  /// \brief `model` (the plant's, as the set-up gives it) with A, B and B1r replaced by those
  /// given here (unchanged when the section is empty: the same values).
  DesignModel over(DesignModel model) const;
};

/// \brief Controller parameters (key `controller`); see config/controller/default.yaml.
struct ControllerConfig : ControllerParams {
  RobustConfig robust;       ///< pa_robust (optional section `controller.robust`)
  L1Config l1;               ///< mode l1 (optional section `controller.l1`; docs/research/l1.md)
  DesignModelSection model;  ///< what the controller designs on (optional `controller.model`)

  /// \brief Read the `controller` section for a plant of n states; problems go to the reader.
  /// The mode's name is checked against the registry where the parts are put together
  /// (checkModeName in mode_registry.hpp, called by the set-up), not here: the registry knows
  /// every law and strategy, and they know this configuration.
  static ControllerConfig read(ParamReader& r, int n, const std::string& prefix = "controller");
  /// \brief Every problem with the values (signs, sizes, finiteness) into the reader.
  void validate(ParamReader& r, int n, const std::string& prefix = "controller") const;
};

/// \brief The parameters that may change while the controller runs (dynamic_reconfigure): the
/// table rows with a `tunable` name. Controller::setTunables queues them; they take effect at
/// the start of the next step().
struct ControllerTunables : ControllerTunableParams {
  /// \brief The tunables of a configuration.
  static ControllerTunables of(const ControllerConfig& c);
  /// \brief Write these values into a configuration.
  void applyTo(ControllerConfig* c) const;
};

}  // namespace preadaptive_mrac
