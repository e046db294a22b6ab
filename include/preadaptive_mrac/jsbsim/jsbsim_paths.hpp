#pragma once
/// \file jsbsim_paths.hpp
/// \brief Where JSBSim and its aircraft are (the binary, JSBSim's --root), and what a message
/// that did not find or could not run JSBSim tells the user to do.

#include <string>

namespace preadaptive_mrac {

/// \brief How to install JSBSim and point to it: the end of the messages that did not find it
/// or could not run it.
extern const char* const kJsbsimInstallHint;

/// \brief The JSBSim binary to run: `configured` when not empty (it must be executable), else
/// the first of $PMRAC_JSBSIM, /usr/games/JSBSim and the build folder's jsbsim/bin/JSBSim
/// (scripts/install_jsbsim). Throws JsbsimError naming the places tried and the fix.
std::string findJsbsimExecutable(const std::string& configured);
/// \brief JSBSim's --root: `configured` when not empty, else the package's
/// share/preadaptive_mrac/jsbsim found from the running executable (as config/ is), else
/// ./jsbsim. Throws JsbsimError when the aircraft folder is not there.
std::string findJsbsimRoot(const std::string& configured, const std::string& aircraft);
/// \brief A new private folder $TMPDIR (else /tmp)/`prefix`XXXXXX for a run's files (the
/// lockstep script and log, an aircraft overlay). Throws JsbsimError when it cannot be made.
std::string makeJsbsimTempDir(const std::string& prefix);

}  // namespace preadaptive_mrac
