#pragma once
/// \file tunables.hpp
/// \brief Checking and comparing ControllerTunables (the parameters dynamic_reconfigure may
/// change while the controller runs) with the same validation as the YAML.

#include <string>
#include <vector>

#include "preadaptive_mrac/core/controller/controller_config.hpp"
#include "preadaptive_mrac/core/schema/params.hpp"

namespace preadaptive_mrac {

/// \brief One tunable as a number: its key below `controller` ("attention.c_ed") and value
/// (bools 0/1, ints exactly).
struct TunableEntry {
  std::string key;
  double value = 0.0;
};

/// \brief Every tunable of `t`, in a fixed order (the order of ControllerTunables).
std::vector<TunableEntry> tunableEntries(const ControllerTunables& t);

/// \brief One changed tunable.
struct TunableChange {
  std::string key;  ///< below `controller` ("attention.c_ed")
  double old_value = 0.0;
  double new_value = 0.0;
};

/// \brief The tunables that differ between `from` and `to`, in tunableEntries order.
std::vector<TunableChange> diffTunables(const ControllerTunables& from,
                                        const ControllerTunables& to);

/// \brief Every problem of `base` with `t` applied, from ControllerConfig::validate (the YAML's
/// validation), each naming its key in `style` below `prefix`
/// ("controller.attention.c_ed: must be > 0, got 0"). The projection keys are checked when
/// projection is enabled or theta_max / epsilon differ from `base`.
std::vector<std::string> validateTunables(const ControllerConfig& base, const ControllerTunables& t,
                                          const KeyStyle& style = KeyStyle(),
                                          const std::string& prefix = "controller");

}  // namespace preadaptive_mrac
