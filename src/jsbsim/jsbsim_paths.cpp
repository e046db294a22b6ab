/// \file jsbsim_paths.cpp
/// \brief Where JSBSim and its aircraft are: the binary and JSBSim's --root, each from the
/// configuration, else searched (environment, system, the package's own folders).

#include "preadaptive_mrac/jsbsim/jsbsim_paths.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

#include "preadaptive_mrac/jsbsim/jsbsim_process.hpp"

namespace preadaptive_mrac {

const char* const kJsbsimInstallHint =
    "install it with scripts/install_jsbsim (extracts /usr/games/JSBSim from Debian's "
    "flightgear package, 13 MB, no FlightGear install) and point to it with "
    "PMRAC_JSBSIM=$(scripts/install_jsbsim | tail -n1) or plant.jsbsim.executable";

namespace {

bool isExecutable(const std::string& path) {
  return !path.empty() && ::access(path.c_str(), X_OK) == 0 && !std::filesystem::is_directory(path);
}

/// The running executable's folder and its parents up to `levels` above.
std::vector<std::filesystem::path> exeAncestors(int levels) {
  std::vector<std::filesystem::path> out;
  std::error_code ec;
  std::filesystem::path p = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return out;
  p = p.parent_path();
  for (int i = 0; i <= levels && !p.empty(); ++i) {
    out.push_back(p);
    if (p == p.parent_path()) break;
    p = p.parent_path();
  }
  return out;
}

}  // namespace

std::string findJsbsimExecutable(const std::string& configured) {
  if (!configured.empty()) {
    if (isExecutable(configured)) return configured;
    throw JsbsimError("plant.jsbsim.executable: '" + configured +
                      "' is not an executable file; leave it empty to search $PMRAC_JSBSIM, "
                      "/usr/games/JSBSim and the build folder, or " +
                      kJsbsimInstallHint);
  }
  std::vector<std::string> tried;
  if (const char* env = std::getenv("PMRAC_JSBSIM")) {
    if (isExecutable(env)) return env;
    tried.push_back(std::string("$PMRAC_JSBSIM (") + env + ")");
  } else {
    tried.push_back("$PMRAC_JSBSIM (unset)");
  }
  if (isExecutable("/usr/games/JSBSim")) return "/usr/games/JSBSim";
  tried.push_back("/usr/games/JSBSim");
  // scripts/install_jsbsim puts it in <build>/jsbsim/bin: the batch tools run from
  // <build>/devel/bin, the tests and nodes from <build>/devel/lib/preadaptive_mrac.
  for (const auto& dir : exeAncestors(3)) {
    const std::string cand = (dir / "jsbsim/bin/JSBSim").string();
    if (isExecutable(cand)) return cand;
    tried.push_back(cand);
  }
  std::string list;
  for (const auto& t : tried) list += (list.empty() ? "" : ", ") + t;
  throw JsbsimError("JSBSim not found (plant.engine is jsbsim; tried " + list +
                    "): " + kJsbsimInstallHint);
}

std::string findJsbsimRoot(const std::string& configured, const std::string& aircraft) {
  std::vector<std::string> cands;
  if (!configured.empty()) {
    cands.push_back(configured);
  } else {
    if (const char* env = std::getenv("PREADAPTIVE_MRAC_JSBSIM_ROOT")) cands.push_back(env);
    for (const auto& dir : exeAncestors(2))
      cands.push_back((dir / "share/preadaptive_mrac/jsbsim").lexically_normal().string());
    cands.push_back("jsbsim");
  }
  for (const auto& c : cands) {
    if (std::filesystem::is_regular_file(c + "/aircraft/" + aircraft + "/" + aircraft + ".xml"))
      return std::filesystem::absolute(c).lexically_normal().string();
  }
  std::string list;
  for (const auto& c : cands) list += (list.empty() ? "" : ", ") + c;
  if (!configured.empty())
    throw JsbsimError("plant.jsbsim.aircraft: no aircraft '" + aircraft +
                      "' in plant.jsbsim.root '" + configured + "' (expected " + configured +
                      "/aircraft/" + aircraft + "/" + aircraft + ".xml)");
  throw JsbsimError("plant.jsbsim.aircraft: no aircraft '" + aircraft + "' (looked for aircraft/" +
                    aircraft + "/" + aircraft + ".xml under " + list +
                    "); the package's aircraft is b747_pmrac, or give plant.jsbsim.root");
}

std::string makeJsbsimTempDir(const std::string& prefix) {
  const char* tmp = std::getenv("TMPDIR");
  std::string templ = std::string(tmp && *tmp ? tmp : "/tmp") + "/" + prefix + "XXXXXX";
  std::vector<char> t(templ.begin(), templ.end());
  t.push_back('\0');
  if (::mkdtemp(t.data()) == nullptr)
    throw JsbsimError("JSBSim: cannot make a temporary folder " + templ + ": " +
                      std::strerror(errno));
  return t.data();
}

}  // namespace preadaptive_mrac
