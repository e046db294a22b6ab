#pragma once
/// \file mode_context.hpp
/// \brief What the factories of laws and strategies get (mode_registry.hpp): apart from the
/// registry, so a part's factory does not include the registry that includes the part.

#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

struct ControllerDesign;
struct ControllerParams;
struct L1Config;
struct RobustParams;
class PreadaptNetwork;

/// \brief What a law's or a strategy's factory gets: the controller's parameters and its
/// parts', the design model (the plant as the controller knows it), the design (K, P, A_r) and
/// the network the controller owns. Defined here, below the controller that fills it in, so
/// the laws and strategies never include the controller's headers.
struct ModeContext {
  const ControllerParams* cfg = nullptr;  ///< `controller` (gains, sample time, projection)
  const L1Config* l1 = nullptr;           ///< `controller.l1`
  const RobustParams* robust = nullptr;   ///< `controller.robust`
  const ControllerDesign* design = nullptr;
  const Eigen::MatrixXd* A = nullptr;    ///< design model's A
  const Eigen::VectorXd* B1r = nullptr;  ///< design model's B1r
  const Eigen::VectorXd* x0 = nullptr;   ///< initial state the controller assumes
  const Vec* B = nullptr;                ///< plant input vector
  const Vec* PB = nullptr;               ///< P B
  int out = 1;                           ///< index of the output alpha in x
  PreadaptNetwork* net = nullptr;
};

}  // namespace preadaptive_mrac
