#pragma once
/// \file mode_context.hpp
/// \brief What the factories of laws and strategies get (mode_registry.hpp): apart from the
/// registry, so a part's factory does not include the registry that includes the part.

#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

struct ControllerConfig;
struct ControllerDesign;
struct PlantConfig;
class PreadaptNetwork;

/// \brief What a law's or a strategy's factory gets: the configuration, the plant as the
/// controller knows it, the design (K, P, A_r) and the network the controller owns.
struct ModeContext {
  const ControllerConfig* cfg = nullptr;
  const PlantConfig* plant = nullptr;
  const ControllerDesign* design = nullptr;
  const Vec* B = nullptr;   ///< plant input vector
  const Vec* PB = nullptr;  ///< P B
  int out = 1;              ///< index of the output alpha in x
  PreadaptNetwork* net = nullptr;
};

}  // namespace preadaptive_mrac
