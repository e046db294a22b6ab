#pragma once
/// \file mode_context.hpp
/// \brief What the factories of laws and strategies get (mode_registry.hpp): apart from the
/// registry, so a part's factory does not include the registry that includes the part.

#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

struct ControllerDesign;
struct ControllerParams;
struct DesignModel;
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
  const DesignModel* model = nullptr;  ///< the plant as the controller knows it (design_model.hpp)
  const Vec* B = nullptr;              ///< the design model's B
  const Vec* PB = nullptr;             ///< P B
  PreadaptNetwork* net = nullptr;
};

}  // namespace preadaptive_mrac
