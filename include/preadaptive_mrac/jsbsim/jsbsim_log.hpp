#pragma once
/// \file jsbsim_log.hpp
/// \brief Reading JSBSim's own output for the reason it gave up (STL only): the lines the
/// Debian 2020.3 binary prints when an aircraft, one of its files or an initial condition does
/// not load, or a property the package uses is missing, turned into a message that names the
/// cause and the key to look at.

#include <cstddef>
#include <string>

namespace preadaptive_mrac {

/// \brief The names a message about the aircraft's files needs.
struct JsbsimNames {
  std::string aircraft;    ///< plant.jsbsim.aircraft
  std::string initialize;  ///< plant.jsbsim.initialize
  std::string root;        ///< JSBSim's --root (plant.jsbsim.root or the package's)
};

/// \brief Why JSBSim gave up, as far as its output says.
struct JsbsimFault {
  std::string key;    ///< the parameter(s) to look at, e.g. "plant.jsbsim.initialize"
  std::string cause;  ///< what is wrong, in the package's words
  std::string said;   ///< JSBSim's own line naming it (empty: nothing fatal in the output)
  /// True when `said` is a line JSBSim prints only as it gives up; false for a property lookup
  /// that failed, which is fatal only when nothing else answers (a refused `get` is not).
  bool certain = false;

  bool found() const { return !said.empty(); }
  /// \brief "<key>: <cause>; JSBSim said: \"<said>\"".
  std::string message() const;
};

/// \brief The most specific reason in `log` (JSBSim's stdout and stderr, or the part of it
/// written since a point) why JSBSim stopped or cannot go on; found() is false when it holds
/// none of JSBSim's fatal lines.
JsbsimFault diagnoseJsbsimLog(const std::string& log, const JsbsimNames& names);

/// \brief True for JSBSim's replies to a command it refused for its property ("Unknown
/// property", "No property argument supplied.", "Badly formed property query"): JSBSim then
/// drops the rest of the packet, whose commands get no reply at all.
bool jsbsimRefusedProperty(const std::string& reply);

/// \brief The last `max_lines` lines of `log` that say something (JSBSim's banner and blank
/// lines left out), joined by " | "; "(no output)" when there are none.
std::string jsbsimLogTail(const std::string& log, size_t max_lines);

}  // namespace preadaptive_mrac
