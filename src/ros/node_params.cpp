#include "preadaptive_mrac/ros/node_params.hpp"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <optional>
#include <set>

#include "preadaptive_mrac/core/schema/param_table.hpp"
#include "preadaptive_mrac/io/weights_io.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_overlay.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_process.hpp"
#include "preadaptive_mrac/ros/publisher_guard.hpp"

namespace preadaptive_mrac {
namespace ros1 {
namespace {

/// The node's own rows of params/nodes.yaml (P: a generated struct): each read with its default
/// and range-checked, and every key not one of P's or `extra` rejected (typos such as ~clok
/// should not pass silently). The plant and controller nodes pass the config sections (plant,
/// controller, scenario) as `extra`, so that one layered YAML can be loaded into either.
template <class P>
void readNodeRows(ParamReader& r, const ParamValue& tree, P* p,
                  const std::vector<std::string>& extra) {
  readScalars(r, "", p);
  checkRanges(r, "", *p);
  std::set<std::string> known(extra.begin(), extra.end());
  P::forEachKey([&](const char* key) { known.insert(key); });
  if (tree.type() != ParamValue::Type::kMap) return;
  for (const auto& kv : tree.map()) {
    if (known.count(kv.first) == 0) r.fail(kv.first, "unknown parameter");
  }
}

/// The config sections (plant, controller, scenario) the plant and controller nodes allow, and
/// `more`.
std::vector<std::string> configSectionsAnd(std::initializer_list<const char*> more = {}) {
  std::vector<std::string> keys = {"plant", "controller", "scenario"};
  keys.insert(keys.end(), more.begin(), more.end());
  return keys;
}

/// A list of strings (a row read `custom`: no table row can say what each entry must be). False
/// when `key` is absent. Given, it must be a list (else a problem: "expected <list_what>, got
/// ..."); each entry that is not a string, or that `why_not` finds fault with (its text; "" =
/// fine), is a problem naming the entry (".../key/1") and left out of `out`.
bool readStringList(ParamReader& r, const ParamValue& tree, const std::string& key,
                    const std::string& list_what, const std::string& entry_what,
                    const std::function<std::string(const std::string&)>& why_not,
                    std::vector<std::string>* out) {
  const ParamValue* v = tree.findPath(key);
  if (v == nullptr) return false;
  if (v->type() != ParamValue::Type::kList) {
    r.fail(key, "expected " + list_what + ", got " + ParamValue::typeName(v->type()) + " " +
                    v->describe());
    return true;
  }
  for (std::size_t i = 0; i < v->list().size(); ++i) {
    const ParamValue& e = v->list()[i];
    const std::string entry = key + "." + std::to_string(i);
    if (e.type() != ParamValue::Type::kString) {
      r.fail(entry, "expected " + entry_what + " (string), got " + ParamValue::typeName(e.type()) +
                        " " + e.describe());
      continue;
    }
    const std::string why = why_not(e.asString());
    if (why.empty())
      out->push_back(e.asString());
    else
      r.fail(entry, "'" + e.asString() + "' " + why);
  }
  return true;
}

/// A required, non-empty list of topic names (~topics, ~state_topics).
std::vector<std::string> readTopicList(ParamReader& r, const ParamValue& tree,
                                       const std::string& key, const std::string& list_what) {
  std::vector<std::string> out;
  const ParamValue* v = tree.findPath(key);
  if (v == nullptr) {
    r.fail(key, "missing: expected " + list_what);
  } else if (v->type() == ParamValue::Type::kList && v->list().empty()) {
    r.fail(key, "expected " + list_what + ", got []");
  } else {
    const auto any = [](const std::string&) { return std::string(); };
    readStringList(r, tree, key, list_what, "a topic name", any, &out);
  }
  return out;
}

/// ~accept_from: a list of node names (PublisherGuard); absent or [] = any publisher. Each
/// entry that is not a string or not a node name is a problem naming it (".../accept_from/1").
std::vector<std::string> readCallerList(ParamReader& r, const ParamValue& tree,
                                        const std::string& key) {
  std::vector<std::string> out;
  const auto why_not = [](const std::string& name) {
    std::string why;
    return validCallerName(name, &why) ? std::string() : "is not a node name: " + why;
  };
  if (!readStringList(r, tree, key,
                      "a list of node names (e.g. [/mrac_controller]; [] = any publisher)",
                      "a node name", why_not, &out))
    r.noteDefault(key, "[] (any publisher)");
  return out;
}

void appendProblems(std::vector<std::string>* out, const std::vector<std::string>& in) {
  out->insert(out->end(), in.begin(), in.end());
}

/// ~elevator_from_aircraft: `tree` with plant.actuator's enabled, max_deflection and max_rate set
/// to the elevator of its JSBSim aircraft (the values preadapt_sim sets when no --elevator is
/// given), so the plant section is then read, checked and used as if the plant file had them.
/// A plant section that does not read is returned as it is (its problems are reported by the
/// caller's readRunConfig); the cases with no aircraft elevator to take are problems of `r`.
/// `note` gets one line saying where the elevator came from.
ParamValue withAircraftElevator(ParamReader& r, const ParamValue& tree, const KeyStyle& style,
                                std::string* note) {
  const std::string key = "elevator_from_aircraft";
  Sections plant_only;
  plant_only.controller = false;
  plant_only.scenario = false;
  PlantConfig plant;
  try {
    plant = readRunConfig(tree, style, plant_only).plant;
  } catch (const ConfigError&) {
    return tree;
  }
  if (plant.engine != PlantEngineKind::kJsbsim) {
    r.fail(key,
           "needs plant.engine jsbsim (the elevator is read from the JSBSim aircraft's flight "
           "control system)");
    return tree;
  }
  const std::string& aircraft = plant.jsbsim.aircraft;
  std::optional<JsbsimElevator> el;
  try {
    el = jsbsimOrdinaryElevator(plant.jsbsim);
  } catch (const JsbsimError& e) {
    r.fail(key, std::string("cannot read the aircraft's elevator: ") + e.what());
    return tree;
  }
  if (!el) {
    r.fail(key, "the aircraft '" + aircraft +
                    "' carries the package's interface: its elevator is the plant file's (the "
                    "launch files: elevator:=b747, or a file)");
    return tree;
  }
  if (!el->limitsKnown()) {
    r.fail(key, "the aircraft '" + aircraft +
                    "' gives no elevator travel and rate in its flight control system: give the "
                    "elevator in a file (the launch files: elevator:=FILE)");
    return tree;
  }
  ParamValue out = tree;
  out.setPath("plant.actuator.enabled", ParamValue::makeBool(true));
  out.setPath("plant.actuator.max_deflection", ParamValue::makeDouble(el->symmetricTravel()));
  out.setPath("plant.actuator.max_rate", ParamValue::makeDouble(el->max_rate));
  *note = "plant.actuator from the aircraft '" + aircraft + "': travel " +
          formatNumber(el->symmetricTravel()) + " rad, rate " + formatNumber(el->max_rate) +
          " rad/s (" + el->writer + ")";
  return out;
}

}  // namespace

std::string defaultsLine(const std::vector<std::string>& defaults_used) {
  std::string line = "optional keys filled with defaults: ";
  if (defaults_used.empty()) return line + "none";
  for (size_t i = 0; i < defaults_used.size(); ++i) line += (i ? ", " : "") + defaults_used[i];
  return line;
}

const char* clockModeName(ClockMode m) { return choiceName(m); }

PlantNodeParams readPlantNodeParams(const ParamValue& tree, const KeyStyle& style) {
  PlantNodeParams p;
  ParamReader r(tree, style);
  readNodeRows(r, tree, &p, configSectionsAnd());
  for (const char* key : {"world_frame", "body_frame", "velocity_frame"}) {
    if (r.usable(key) && r.getString(key).empty()) r.fail(key, "must not be empty");
  }
  if (p.world_frame == p.body_frame || p.body_frame == p.velocity_frame ||
      p.world_frame == p.velocity_frame)
    r.fail("body_frame", "world, body and velocity frames must differ (world='" + p.world_frame +
                             "', body='" + p.body_frame + "', velocity='" + p.velocity_frame +
                             "')");
  p.accept_from = readCallerList(r, tree, "accept_from");
  // A program the plant runs is never taken from the parameter server, which any node may write
  // before the plant starts: the JSBSim binary comes from the environment the user starts the
  // launch with ($PMRAC_JSBSIM, the launch files' jsbsim arg) or the search.
  if (tree.findPath("plant.jsbsim.executable") != nullptr)
    r.fail("plant.jsbsim.executable",
           "not taken from the parameter server (any node can set it): give the JSBSim binary "
           "as $PMRAC_JSBSIM or the launch argument jsbsim:=PATH, or leave both empty to search "
           "/usr/games/JSBSim and the build folder");
  // Written at the end of the run: a file already there (an earlier run's report) is kept.
  std::error_code ec;
  if (!p.latency_report.empty() && std::filesystem::exists(p.latency_report, ec))
    r.fail("latency_report",
           "'" + p.latency_report + "' exists: not replaced (remove it or name a new file)");

  std::string elevator_note;
  const ParamValue config =
      p.elevator_from_aircraft ? withAircraftElevator(r, tree, style, &elevator_note) : tree;
  std::vector<std::string> problems = r.problems();
  try {
    Sections s;
    s.plant = true;
    s.controller = false;
    s.scenario = true;
    p.run = readRunConfig(config, style, s);
    if (!elevator_note.empty()) p.run.derived.push_back(elevator_note);
    // the plant's step is its own ~dt (the controller's is checked with its sample_time)
    if (r.usable("dt")) {
      const std::string why = runLengthProblem(p.run.scenario.endTime(), p.dt);
      if (!why.empty()) problems.push_back(r.name("dt") + ": " + why);
    }
  } catch (const ConfigError& e) {
    appendProblems(&problems, e.problems());
  }
  if (!problems.empty()) throw ConfigError(problems);
  p.defaults_used = r.defaultsUsed();
  appendProblems(&p.defaults_used, p.run.defaults_used);
  return p;
}

ControllerNodeParams readControllerNodeParams(const ParamValue& tree, const KeyStyle& style) {
  ControllerNodeParams p;
  ParamReader r(tree, style);
  // (~reconfigure/* is written by the dynamic_reconfigure server, never read)
  readNodeRows(r, tree, &p, configSectionsAnd({"reconfigure"}));
  p.accept_from = readCallerList(r, tree, "accept_from");

  std::string elevator_note;
  const ParamValue config =
      p.elevator_from_aircraft ? withAircraftElevator(r, tree, style, &elevator_note) : tree;
  std::vector<std::string> problems = r.problems();
  bool run_ok = false;
  try {
    Sections s;
    s.plant = true;
    s.controller = true;
    s.scenario = false;
    p.run = readRunConfig(config, style, s);
    if (!elevator_note.empty()) p.run.derived.push_back(elevator_note);
    run_ok = true;
  } catch (const ConfigError& e) {
    appendProblems(&problems, e.problems());
  }
  // Saved over and over during the run: a file already there (another run's network) is kept,
  // unless it is the ~weights_in this run continues.
  std::error_code ec;
  if (!p.weights_out.empty() && std::filesystem::exists(p.weights_out, ec) &&
      !(!p.weights_in.empty() && std::filesystem::equivalent(p.weights_out, p.weights_in, ec)))
    problems.push_back(r.name("weights_out") + ": '" + p.weights_out +
                       "' exists: not replaced (remove it, name a new file, or give the same file "
                       "as ~weights_in to continue the network saved there)");
  if (!p.weights_in.empty()) {
    // Check the file now, with the sizes when the config is known, so that a bad weights
    // file is reported together with every other problem instead of after start-up.
    try {
      if (run_ok) {
        loadWeights(p.weights_in, p.run.controller.hidden, p.run.plant.n());
      } else {
        loadWeights(p.weights_in);
      }
    } catch (const std::exception& e) {
      problems.push_back(r.name("weights_in") + ": " + e.what());
    }
  }
  if (!problems.empty()) throw ConfigError(problems);
  p.defaults_used = r.defaultsUsed();
  appendProblems(&p.defaults_used, p.run.defaults_used);
  return p;
}

BagRecorderParams readBagRecorderParams(const ParamValue& tree, const KeyStyle& style,
                                        const std::vector<std::string>& message_types) {
  BagRecorderParams p;
  ParamReader r(tree, style);
  readNodeRows(r, tree, &p, {});
  p.topics = readTopicList(r, tree, "topics", "a non-empty list of topic names");
  const auto why_not = [&](const std::string& type) {
    return std::find(message_types.begin(), message_types.end(), type) != message_types.end()
               ? std::string()
               : "is not one of this package's messages or tf2_msgs/TFMessage (\"\" records any "
                 "type)";
  };
  const std::string types_what =
      "a list of " + std::to_string(p.topics.size()) + " type names, one per ~topics entry";
  if (!readStringList(r, tree, "types", types_what, "a type name", why_not, &p.types)) {
    r.noteDefault("types", "[] (every topic untyped)");
  } else if (r.usable("types") && r.usable("topics") &&
             tree.findPath("types")->list().size() != p.topics.size()) {
    r.fail("types", "expected " + types_what + ", got " + tree.findPath("types")->describe());
  }
  if (p.output.empty() && p.output_prefix.empty())
    r.fail("output", "set ~output or ~output_prefix");
  p.accept_from = readCallerList(r, tree, "accept_from");
  if (!r.problems().empty()) throw ConfigError(r.problems());
  p.defaults_used = r.defaultsUsed();
  return p;
}

RunMonitorParams readRunMonitorParams(const ParamValue& tree, const KeyStyle& style) {
  RunMonitorParams p;
  ParamReader r(tree, style);
  readNodeRows(r, tree, &p, {});
  p.state_topics =
      readTopicList(r, tree, "state_topics", "a non-empty list of PlantState topic names");
  p.accept_from = readCallerList(r, tree, "accept_from");
  if (!r.problems().empty()) throw ConfigError(r.problems());
  p.defaults_used = r.defaultsUsed();
  return p;
}

}  // namespace ros1
}  // namespace preadaptive_mrac
