#pragma once
/// \file robust_config.hpp
/// \brief pa_robust's parameters (key `controller.robust`): owned by the strategy. The values,
/// defaults, docs and ranges are its table's (params/robust.yaml, generated into RobustParams);
/// the checks between keys are here.

#include <string>

#include "preadaptive_mrac/params/robust_params.hpp"

namespace preadaptive_mrac {

class ParamReader;

/// \brief Parameters of pa_robust (key `controller.robust`; docs/research/robust.md).
struct RobustConfig : RobustParams {
  /// \brief Read the optional section at `prefix`: absent, every default; each key optional.
  static RobustConfig read(ParamReader& r, const std::string& prefix);
  /// \brief The table's ranges and the checks between keys, each problem naming its key.
  void validate(ParamReader& r, const std::string& prefix) const;
};

}  // namespace preadaptive_mrac
