#pragma once
/// \file weights_io.hpp
/// \brief The preadaptation network's weights file (YAML): format, version, sizes, seed,
/// episodes, V and W at full precision, and the regimes pa_robust remembers. Saved atomically;
/// loads refuse anything suspicious.

#include <stdexcept>
#include <string>

#include "preadaptive_mrac/core/control/network.hpp"

namespace preadaptive_mrac {

/// \brief A weights file that cannot be used; the message names the file and the field.
class WeightsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// \brief Current format version written by saveWeights. Version 2 adds `regimes:` (the
/// memory of pa_robust); version 3 each regime's loss of elevator effectiveness (`loss`,
/// `loss_info`). Version 1 files (no regimes) still load, with an empty memory; version 2
/// files with no loss identified.
constexpr int kWeightsFormatVersion = 3;

/// \brief Text of a weights file (17 significant digits, so a load gives identical weights).
std::string weightsToYaml(const LearnedState& s);
/// \brief Write to `path` atomically: a temporary file beside it, fsync, rename. On failure
/// the previous file is untouched and WeightsError is thrown.
void saveWeights(const std::string& path, const LearnedState& s);
/// \brief Read and check a weights file: format tag, version, sizes (V 2 x hidden,
/// W hidden x outputs) against what the caller expects (< 0: any), finite numbers.
LearnedState loadWeights(const std::string& path, int expected_hidden = -1,
                         int expected_outputs = -1);
/// \brief The same from text; `origin` names it in errors.
LearnedState parseWeights(const std::string& text, const std::string& origin,
                          int expected_hidden = -1, int expected_outputs = -1);

}  // namespace preadaptive_mrac
