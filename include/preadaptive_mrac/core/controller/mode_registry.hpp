#pragma once
/// \file mode_registry.hpp
/// \brief The registered modes: each a name, one line of doc, an adaptive law and a
/// preadaptation strategy. The one list of modes is params/modes.yaml: its rows, generated into
/// preadaptive_mrac/params/modes_params.hpp, make this registry (the CLI's --mode, --modes and
/// --list-modes, the sweeps, families and nodes, the validation message of `controller.mode`);
/// the Python package (preadaptive_mrac.modes), the launch files (scripts/lib/mode_info) and the
/// docs read the same table.
///
/// A mode users see is one row of params/modes.yaml naming a registered law and strategy
/// (control/part_registry.hpp: the built-in ones are registered here, a new one in its own
/// folder with one line); a program may add a mode of registered parts with registerMode (a
/// test does), listed after the table's.

#include <deque>
#include <string>
#include <vector>

#include "preadaptive_mrac/core/control/mode_context.hpp"
#include "preadaptive_mrac/core/control/part_registry.hpp"

namespace preadaptive_mrac {

class ParamReader;

/// \brief One registered mode.
struct ModeEntry {
  const char* name;  ///< what `controller.mode` and --mode take
  const char* doc;   ///< one line: what the mode does
  LawFactory make_law;
  StrategyFactory make_strategy;
  bool truth;  ///< reads the simulation's true theta (params/modes.yaml `truth`)
};

/// \brief Add the mode `name` (with its one line of `doc`) of the registered law `law` and
/// strategy `strategy`; `truth`: its strategy reads the simulation's true theta (its
/// needsTruth()). Listed after params/modes.yaml's rows, in the order registered: --mode,
/// --list-modes, `controller.mode` and the default --modes take it. Register it after its
/// parts (below them in the same file: a file's static initialisers run in order). Returns
/// true; throws std::logic_error naming `name` when it is empty or a mode of that name exists
/// (in the table or registered), or naming the law or strategy that is not registered.
bool registerMode(const std::string& name, const std::string& doc, const std::string& law,
                  const std::string& strategy, bool truth);

/// \brief Every mode: params/modes.yaml's rows in the table's order, then the registered ones in
/// theirs. A deque: a registration never moves the entries findMode handed out.
const std::deque<ModeEntry>& modeRegistry();
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
