#include "preadaptive_mrac/jsbsim/jsbsim_log.hpp"

#include <sstream>
#include <vector>

namespace preadaptive_mrac {

namespace {

// Lines JSBSim 2020.3 prints only as it gives up (it exits right after them).
const char* const kGiveUp[] = {"FATAL ERROR",
                               "was not successfully loaded",
                               "could not be loaded",
                               "could not be read",
                               "is not a reset file",
                               "has problems in file",
                               "failed to open the configuration file"};
// A property lookup that failed: a load that ends, or a socket command refused.
const char kNoNode[] = "No node found for ";

std::string trimmed(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return {};
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

std::vector<std::string> linesOf(const std::string& log) {
  std::vector<std::string> out;
  std::stringstream ss(log);
  std::string line;
  while (std::getline(ss, line)) {
    line = trimmed(line);
    if (!line.empty()) out.push_back(line);
  }
  return out;
}

bool has(const std::string& line, const char* needle) {
  return line.find(needle) != std::string::npos;
}

/// The first (or the last) line holding `needle`; empty when none does.
std::string lineWith(const std::vector<std::string>& lines, const char* needle, bool last = false) {
  std::string found;
  for (const auto& l : lines) {
    if (!has(l, needle)) continue;
    found = l;
    if (!last) break;
  }
  return found;
}

/// JSBSim's "Could not open file: <name>" for a file an aircraft names (an engine, thruster or
/// system), as opposed to one given by path ("Could not open file: Path \"...\"").
std::string namedFileLine(const std::vector<std::string>& lines) {
  const std::string open = "Could not open file: ";
  for (const auto& l : lines)
    if (l.compare(0, open.size(), open) == 0 && l.compare(open.size(), 5, "Path ") != 0) return l;
  return {};
}

/// JSBSim's "No <element> element was found in the aircraft config file."
std::string missingElementLine(const std::vector<std::string>& lines) {
  for (const auto& l : lines)
    if (l.compare(0, 3, "No ") == 0 && has(l, " element was found")) return l;
  return {};
}

std::string aircraftFile(const JsbsimNames& n) {
  return n.root + "/aircraft/" + n.aircraft + "/" + n.aircraft + ".xml";
}

std::string icFile(const JsbsimNames& n) {
  return n.root + "/aircraft/" + n.aircraft + "/" + n.initialize + ".xml";
}

JsbsimFault fault(const char* key, const std::string& cause, const std::string& said) {
  JsbsimFault f;
  f.key = key;
  f.cause = cause;
  f.said = said;
  return f;
}

/// An engine, thruster or system file the aircraft names that JSBSim did not find.
JsbsimFault namedFileFault(const std::vector<std::string>& lines, const std::string& said,
                           const JsbsimNames& n) {
  const std::string where = lineWith(lines, "In file ");
  const std::string engines = "its folder's Engines/ and " + n.root + "/engine";
  const std::string systems = "its folder, its Systems/ and " + n.root + "/systems";
  std::string look =
      "engine and thruster files are looked for in " + engines + ", system files in " + systems;
  if (!lineWith(lines, "propulsion element has problems").empty())
    look = "engine and thruster files are looked for in " + engines;
  if (!lineWith(lines, "system element has problems").empty())
    look = "system files are looked for in " + systems;
  return fault("plant.jsbsim.aircraft, plant.jsbsim.root",
               "the aircraft '" + n.aircraft + "' names a file that is not there" +
                   (where.empty() ? "" : " (" + where + ")") + ": " + look,
               said);
}

/// The initial condition's own problems, the aircraft file's, then a file the aircraft names.
JsbsimFault fileFault(const std::vector<std::string>& lines, const JsbsimNames& n) {
  const char* const kIc = "plant.jsbsim.initialize";
  const char* const kAircraft = "plant.jsbsim.aircraft";
  std::string l = lineWith(lines, "is not a reset file");
  if (!l.empty())
    return fault(kIc,
                 "the initial condition '" + n.initialize + "' (" + icFile(n) +
                     ") is not an <initialize> file",
                 l);
  l = lineWith(lines, "could not be read");
  if (!l.empty()) {
    const std::string open = lineWith(lines, (n.initialize + ".xml").c_str());
    return fault(kIc, "no initial condition '" + n.initialize + "': JSBSim looks for " + icFile(n),
                 open.empty() ? l : open);
  }
  l = lineWith(lines, "failed to open the configuration file");
  if (!l.empty()) return fault(kAircraft, "no aircraft file " + aircraftFile(n), l);
  l = missingElementLine(lines);
  if (!l.empty())
    return fault(kAircraft,
                 aircraftFile(n) +
                     " is not a JSBSim aircraft (an <fdm_config version=\"2.0\"> "
                     "with metrics, mass_balance, ...)",
                 l);
  l = namedFileLine(lines);
  if (!l.empty()) return namedFileFault(lines, l, n);
  return {};
}

/// A property the aircraft lacks, a failed trim, or JSBSim's exception.
JsbsimFault runFault(const std::vector<std::string>& lines, const JsbsimNames& n) {
  std::string l = lineWith(lines, kNoNode, true);
  if (!l.empty()) {
    const std::string prop = l.substr(l.find(kNoNode) + sizeof kNoNode - 1);
    std::string cause = "the aircraft '" + n.aircraft + "' has no property " + prop;
    if (has(prop, "pmrac"))
      cause +=
          ": it is not an aircraft for the package, which drives it through the properties "
          "of the pmrac-interface system (fcs/pmrac-*, pmrac/*: see "
          "jsbsim/aircraft/b747_pmrac)";
    return fault("plant.jsbsim.aircraft", cause, l);
  }
  l = lineWith(lines, "Trim failed");
  if (!l.empty())
    return fault("plant.jsbsim.mach, plant.jsbsim.altitude_ft",
                 "JSBSim's trim found no trim at this operating point", l);
  l = lineWith(lines, "The message was:");
  if (!l.empty())
    return fault("plant.jsbsim.aircraft, plant.jsbsim.initialize",
                 "JSBSim stopped with an exception", l);
  l = lineWith(lines, "terminated with an unknown exception");
  if (!l.empty())
    return fault("plant.jsbsim.aircraft, plant.jsbsim.initialize",
                 "JSBSim stopped with an unknown exception while reading the aircraft '" +
                     n.aircraft + "' or the initial condition '" + n.initialize +
                     "': the usual cause is a file that is not well-formed XML",
                 l);
  return {};
}

}  // namespace

std::string JsbsimFault::message() const {
  return key + ": " + cause + "; JSBSim said: \"" + said + "\"";
}

JsbsimFault diagnoseJsbsimLog(const std::string& log, const JsbsimNames& names) {
  const std::vector<std::string> lines = linesOf(log);
  bool certain = false, lookup = false;
  for (const auto& l : lines) {
    for (const char* g : kGiveUp) certain = certain || has(l, g);
    lookup = lookup || has(l, kNoNode);
  }
  if (!certain && !lookup) return {};
  JsbsimFault f = fileFault(lines, names);
  if (!f.found()) f = runFault(lines, names);
  if (!f.found()) {
    std::string l;
    for (const char* g : kGiveUp)
      if (l.empty()) l = lineWith(lines, g);
    f = fault("plant.jsbsim.aircraft, plant.jsbsim.initialize, plant.jsbsim.root",
              "JSBSim did not load the aircraft '" + names.aircraft +
                  "' with the initial condition '" + names.initialize + "'",
              l);
  }
  f.certain = certain;
  return f;
}

bool jsbsimRefusedProperty(const std::string& reply) {
  for (const char* r :
       {"Unknown property", "No property argument supplied", "Badly formed property query"})
    if (reply.compare(0, std::char_traits<char>::length(r), r) == 0) return true;
  return false;
}

std::string jsbsimLogTail(const std::string& log, size_t max_lines) {
  std::vector<std::string> lines;
  std::stringstream ss(log);
  std::string line;
  while (std::getline(ss, line)) {
    // (JSBSim's banner and blank lines say nothing about the problem)
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    lines.push_back(line);
  }
  std::string out;
  const size_t from = lines.size() > max_lines ? lines.size() - max_lines : 0;
  for (size_t i = from; i < lines.size(); ++i) out += (out.empty() ? "" : " | ") + lines[i];
  return out.empty() ? "(no output)" : out;
}

}  // namespace preadaptive_mrac
