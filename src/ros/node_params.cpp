#include "preadaptive_mrac/ros/node_params.hpp"

#include <initializer_list>
#include <set>

#include "preadaptive_mrac/core/param_table.hpp"
#include "preadaptive_mrac/io/weights_io.hpp"
#include "preadaptive_mrac/ros/publisher_guard.hpp"

namespace preadaptive_mrac {
namespace ros1 {
namespace {

/// The node's own rows of params/nodes.yaml (P: a generated struct): each read with its default
/// and range-checked, and every key not one of P's, the config sections or `extra` rejected
/// (typos such as ~clok should not pass silently). The config sections (plant, controller,
/// scenario) are allowed in both nodes so that one layered YAML can be loaded into either.
template <class P>
void readNodeRows(ParamReader& r, const ParamValue& tree, P* p,
                  std::initializer_list<const char*> extra = {}) {
  readScalars(r, "", p);
  checkRanges(r, "", *p);
  std::set<std::string> known = {"plant", "controller", "scenario"};
  known.insert(extra.begin(), extra.end());
  P::forEachKey([&](const char* key) { known.insert(key); });
  if (tree.type() != ParamValue::Type::kMap) return;
  for (const auto& kv : tree.map()) {
    if (known.count(kv.first) == 0) r.fail(kv.first, "unknown parameter");
  }
}

/// ~accept_from: a list of node names (PublisherGuard); absent or [] = any publisher. Each
/// entry that is not a string or not a node name is a problem naming it (".../accept_from/1").
std::vector<std::string> readCallerList(ParamReader& r, const ParamValue& tree,
                                        const std::string& key) {
  std::vector<std::string> out;
  const ParamValue* v = tree.findPath(key);
  if (v == nullptr) {
    r.noteDefault(key, "[] (any publisher)");
    return out;
  }
  if (v->type() != ParamValue::Type::kList) {
    r.fail(key, std::string("expected a list of node names (e.g. [/mrac_controller]; [] = any "
                            "publisher), got ") +
                    ParamValue::typeName(v->type()) + " " + v->describe());
    return out;
  }
  for (std::size_t i = 0; i < v->list().size(); ++i) {
    const ParamValue& e = v->list()[i];
    const std::string entry = key + "." + std::to_string(i);
    std::string why;
    if (e.type() != ParamValue::Type::kString) {
      r.fail(entry, std::string("expected a node name (string), got ") +
                        ParamValue::typeName(e.type()) + " " + e.describe());
    } else if (!validCallerName(e.asString(), &why)) {
      r.fail(entry, "'" + e.asString() + "' is not a node name: " + why);
    } else {
      out.push_back(e.asString());
    }
  }
  return out;
}

void appendProblems(std::vector<std::string>* out, const std::vector<std::string>& in) {
  out->insert(out->end(), in.begin(), in.end());
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
  readNodeRows(r, tree, &p);
  for (const char* key : {"world_frame", "body_frame", "velocity_frame"}) {
    if (r.usable(key) && r.getString(key).empty()) r.fail(key, "must not be empty");
  }
  if (p.world_frame == p.body_frame || p.body_frame == p.velocity_frame ||
      p.world_frame == p.velocity_frame)
    r.fail("body_frame", "world, body and velocity frames must differ (world='" + p.world_frame +
                             "', body='" + p.body_frame + "', velocity='" + p.velocity_frame +
                             "')");
  p.accept_from = readCallerList(r, tree, "accept_from");

  std::vector<std::string> problems = r.problems();
  try {
    Sections s;
    s.plant = true;
    s.controller = false;
    s.scenario = true;
    p.run = readRunConfig(tree, style, s);
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
  readNodeRows(r, tree, &p, {"reconfigure"});
  p.accept_from = readCallerList(r, tree, "accept_from");

  std::vector<std::string> problems = r.problems();
  bool run_ok = false;
  try {
    Sections s;
    s.plant = true;
    s.controller = true;
    s.scenario = false;
    p.run = readRunConfig(tree, style, s);
    run_ok = true;
  } catch (const ConfigError& e) {
    appendProblems(&problems, e.problems());
  }
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

}  // namespace ros1
}  // namespace preadaptive_mrac
