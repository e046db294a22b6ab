#pragma once
/// \file mode_registry.hpp
/// \brief The registered modes: each a name, one line of doc, an adaptive law and a
/// preadaptation strategy. The one list of modes is params/modes.yaml: its rows, generated into
/// preadaptive_mrac/params/modes_params.hpp, make this registry (the CLI's --mode, --modes and
/// --list-modes, the sweeps, families and nodes, the validation message of `controller.mode`);
/// the Python package (preadaptive_mrac.modes), the launch files (scripts/lib/mode_info) and the
/// docs read the same table.
///
/// A new mode is one row of params/modes.yaml naming a registered law and strategy; a new law
/// (adaptive_law.hpp) or strategy (preadaptation.hpp) is one row of lawRegistry() or
/// strategyRegistry() in src/core/controller/mode_registry.cpp.

#include <memory>
#include <string>
#include <vector>

#include "preadaptive_mrac/core/control/mode_context.hpp"

namespace preadaptive_mrac {

class AdaptiveLaw;
class ParamReader;
class PreadaptationStrategy;

/// \brief One registered mode.
struct ModeEntry {
  const char* name;  ///< what `controller.mode` and --mode take
  const char* doc;   ///< one line: what the mode does
  std::unique_ptr<AdaptiveLaw> (*make_law)(const ModeContext&);
  std::unique_ptr<PreadaptationStrategy> (*make_strategy)(const ModeContext&);
  bool truth;  ///< reads the simulation's true theta (params/modes.yaml `truth`)
};

/// \brief A registered adaptive law: the name params/modes.yaml's `law` gives it.
struct LawEntry {
  const char* name;
  std::unique_ptr<AdaptiveLaw> (*make)(const ModeContext&);
};

/// \brief A registered preadaptation strategy: the name params/modes.yaml's `strategy` gives it.
struct StrategyEntry {
  const char* name;
  std::unique_ptr<PreadaptationStrategy> (*make)(const ModeContext&);
};

/// \brief Every registered adaptive law.
const std::vector<LawEntry>& lawRegistry();
/// \brief Every registered preadaptation strategy.
const std::vector<StrategyEntry>& strategyRegistry();

/// \brief Every registered mode, in the order of the docs and the default --modes.
const std::vector<ModeEntry>& modeRegistry();
/// \brief The entry named `name`, or null.
const ModeEntry* findMode(const std::string& name);
/// \brief A problem naming `key` when `name` (given there) is no registered mode: the
/// check of `controller.mode`, made where the configuration meets the registry (the set-up).
void checkModeName(ParamReader& r, const std::string& key, const std::string& name);
/// \brief The names joined by `sep` ("rac, pa, ..."), the last two by `last_sep` when given
/// ("rac, pa, ... or oracle"), for help and messages.
std::string modeNames(const std::string& sep, const std::string& last_sep = "");
/// \brief The names as a list.
std::vector<std::string> modeNameList();

}  // namespace preadaptive_mrac
