#pragma once
/// \file l1_config.hpp
/// \brief The L1 law's parameters (key `controller.l1`): owned by the law. The values, defaults,
/// docs and ranges are its table's (params/l1.yaml, generated into L1Params); the bound no row
/// can say (Nyquist) is checked here.

#include <string>

#include "preadaptive_mrac/params/l1_params.hpp"

namespace preadaptive_mrac {

class ParamReader;

/// \brief Parameters of the L1 law (optional section `controller.l1`; docs/research/l1.md).
struct L1Config : L1Params {
  /// \brief Read the section at `prefix` (`controller.l1`); every key optional, an absent one
  /// keeps its declared default (params/l1.yaml) and is noted. Problems go to the reader.
  static L1Config read(ParamReader& r, const std::string& prefix);
  /// \brief The table's ranges and the Nyquist bound into the reader. `sample_time` [s] is the
  /// controller's dt: omega dt must stay below pi.
  void validate(ParamReader& r, const std::string& prefix, double sample_time) const;
};

}  // namespace preadaptive_mrac
