#pragma once
/// \file mode_registry.hpp
/// \brief The registered modes: each a name, one line of doc, an adaptive law and a
/// preadaptation strategy. The one list of mode names: the CLI (--mode, --modes, --list-modes),
/// the sweeps, families and nodes, the validation message of `controller.mode`, and, through
/// `preadapt_sim --list-modes`, the Python package, the docs and the comments that name them
/// (test/python/test_mode_names.py compares).
///
/// A new mode is one row of kModes in src/core/mode_registry.cpp: its name, doc, the factory of
/// its law (adaptive_law.hpp) and the factory of its strategy (preadaptation.hpp).

#include <memory>
#include <string>
#include <vector>

#include "preadaptive_mrac/core/mode_context.hpp"

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
};

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
