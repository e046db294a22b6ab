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

#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

struct ControllerConfig;
struct ControllerDesign;
struct PlantConfig;
class AdaptiveLaw;
class PreadaptationStrategy;
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
/// \brief The names joined by `sep` ("rac, pa, ..."), the last two by `last_sep` when given
/// ("rac, pa, ... or oracle"), for help and messages.
std::string modeNames(const std::string& sep, const std::string& last_sep = "");
/// \brief The names as a list.
std::vector<std::string> modeNameList();

}  // namespace preadaptive_mrac
