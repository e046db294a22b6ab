#include "preadaptive_mrac/ros/node_params.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "preadaptive_mrac/io/weights_io.hpp"
#include "preadaptive_mrac/ros/publisher_guard.hpp"

namespace preadaptive_mrac {
namespace ros1 {
namespace {

std::string num(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

/// Keys of the private namespace that no reader knows: typos such as ~clok should not pass
/// silently. The config sections (plant, controller, scenario) are allowed in both nodes so
/// that one layered YAML can be loaded into either.
void rejectUnknownTopLevel(const ParamValue& tree, ParamReader& r,
                           const std::set<std::string>& known) {
  if (tree.type() != ParamValue::Type::kMap) return;
  for (const auto& kv : tree.map()) {
    if (known.count(kv.first) == 0) r.fail(kv.first, "unknown parameter");
  }
}

void requireRange(ParamReader& r, const std::string& key, double v, double lo, double hi,
                  bool lo_open) {
  const bool low_ok = lo_open ? v > lo : v >= lo;
  if (r.has(key) && !(low_ok && v <= hi)) {
    r.fail(key, "must be in " + std::string(lo_open ? "(" : "[") + num(lo) + ", " + num(hi) +
                    "], got " + num(v));
  }
}

int readCount(ParamReader& r, const std::string& key, int def, int lo, int hi) {
  const std::int64_t v = r.getInt(key, def);
  if (v < lo || v > hi) {
    r.fail(key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                    std::to_string(v));
    return def;
  }
  return static_cast<int>(v);
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

// ~clock of the plant and the controller (key "clock"): lockstep | realtime.
ClockMode readClockMode(ParamReader& r, const ParamValue& tree, const std::string& key,
                        ClockMode fallback) {
  const std::string clock =
      r.getString(key, fallback == ClockMode::kLockstep ? "lockstep" : "realtime");
  if (clock == "lockstep") return ClockMode::kLockstep;
  if (clock == "realtime") return ClockMode::kRealtime;
  const ParamValue* value = tree.findPath(key);
  // (a value of the wrong type was already reported by getString)
  if (value != nullptr && value->type() == ParamValue::Type::kString)
    r.fail(key, "expected lockstep or realtime, got '" + clock + "'");
  return fallback;
}

}  // namespace

std::string defaultsLine(const std::vector<std::string>& defaults_used) {
  std::string line = "optional keys filled with defaults: ";
  if (defaults_used.empty()) return line + "none";
  for (size_t i = 0; i < defaults_used.size(); ++i) line += (i ? ", " : "") + defaults_used[i];
  return line;
}

const char* clockModeName(ClockMode m) {
  return m == ClockMode::kLockstep ? "lockstep" : "realtime";
}

PlantNodeParams readPlantNodeParams(const ParamValue& tree, const KeyStyle& style) {
  PlantNodeParams p;
  ParamReader r(tree, style);
  p.dt = r.getDouble("dt", p.dt);
  requireRange(r, "dt", p.dt, 0.0, 1.0, true);
  p.clock = readClockMode(r, tree, "clock", ClockMode::kLockstep);
  p.rate = r.getDouble("rate", p.rate);
  requireRange(r, "rate", p.rate, 0.0, 100000.0, true);
  p.publish_clock = r.getBool("publish_clock", p.publish_clock);
  p.clock_decimation = readCount(r, "clock_decimation", p.clock_decimation, 1, 1000000);
  p.world_frame = r.getString("world_frame", p.world_frame);
  p.body_frame = r.getString("body_frame", p.body_frame);
  p.velocity_frame = r.getString("velocity_frame", p.velocity_frame);
  for (const char* key : {"world_frame", "body_frame", "velocity_frame"}) {
    const ParamValue* v = tree.findPath(key);
    if (v != nullptr && v->type() == ParamValue::Type::kString && v->asString().empty())
      r.fail(key, "must not be empty");
  }
  if (p.world_frame == p.body_frame || p.body_frame == p.velocity_frame ||
      p.world_frame == p.velocity_frame)
    r.fail("body_frame", "world, body and velocity frames must differ (world='" + p.world_frame +
                             "', body='" + p.body_frame + "', velocity='" + p.velocity_frame +
                             "')");
  p.tf_decimation = readCount(r, "tf_decimation", p.tf_decimation, 1, 1000000);
  p.min_state_subscribers = readCount(r, "min_state_subscribers", p.min_state_subscribers, 0, 100);
  p.min_truth_subscribers = readCount(r, "min_truth_subscribers", p.min_truth_subscribers, 0, 100);
  p.start_timeout = r.getDouble("start_timeout", p.start_timeout);
  requireRange(r, "start_timeout", p.start_timeout, 0.0, 1e6, false);
  p.command_timeout = r.getDouble("command_timeout", p.command_timeout);
  requireRange(r, "command_timeout", p.command_timeout, 0.0, 1e6, true);
  p.resend_interval = r.getDouble("resend_interval", p.resend_interval);
  requireRange(r, "resend_interval", p.resend_interval, 0.0, 1e6, false);
  p.wait_for_controller = r.getBool("wait_for_controller", p.wait_for_controller);
  p.shutdown_grace = r.getDouble("shutdown_grace", p.shutdown_grace);
  requireRange(r, "shutdown_grace", p.shutdown_grace, 0.0, 60.0, false);
  p.latency_report = r.getString("latency_report", "");
  p.queue_size = readCount(r, "queue_size", p.queue_size, 0, 100000000);
  p.recorder_progress_topic = r.getString("recorder_progress_topic", "");
  p.max_recorder_lag = readCount(r, "max_recorder_lag", p.max_recorder_lag, 1, 100000000);
  p.cmd_timeout = r.getDouble("cmd_timeout", p.cmd_timeout);
  requireRange(r, "cmd_timeout", p.cmd_timeout, 0.0, 1e6, true);
  p.diagnostic_period = r.getDouble("diagnostic_period", p.diagnostic_period);
  requireRange(r, "diagnostic_period", p.diagnostic_period, 0.0, 3600.0, true);
  p.linger = r.getBool("linger", p.linger);
  p.rt_priority = readCount(r, "rt_priority", p.rt_priority, 0, 99);
  p.cpu_affinity = readCount(r, "cpu_affinity", p.cpu_affinity, -1, 1023);
  p.accept_from = readCallerList(r, tree, "accept_from");
  rejectUnknownTopLevel(tree, r,
                        {"plant",
                         "controller",
                         "scenario",
                         "dt",
                         "clock",
                         "rate",
                         "publish_clock",
                         "clock_decimation",
                         "world_frame",
                         "body_frame",
                         "velocity_frame",
                         "tf_decimation",
                         "min_state_subscribers",
                         "min_truth_subscribers",
                         "start_timeout",
                         "command_timeout",
                         "resend_interval",
                         "wait_for_controller",
                         "shutdown_grace",
                         "latency_report",
                         "queue_size",
                         "recorder_progress_topic",
                         "max_recorder_lag",
                         "rt_priority",
                         "cpu_affinity",
                         "cmd_timeout",
                         "diagnostic_period",
                         "linger",
                         "accept_from"});

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
  p.weights_in = r.getString("weights_in", "");
  p.weights_out = r.getString("weights_out", "");
  p.save_every_episode = r.getBool("save_every_episode", p.save_every_episode);
  p.min_command_subscribers =
      readCount(r, "min_command_subscribers", p.min_command_subscribers, 0, 100);
  p.min_status_subscribers =
      readCount(r, "min_status_subscribers", p.min_status_subscribers, 0, 100);
  p.start_timeout = r.getDouble("start_timeout", p.start_timeout);
  requireRange(r, "start_timeout", p.start_timeout, 0.0, 1e6, false);
  p.truth_buffer = readCount(r, "truth_buffer", p.truth_buffer, 1, 10000000);
  const ParamValue* policy_value = tree.findPath("stale_policy");
  const std::string policy = r.getString("stale_policy", "baseline_hold");
  if (!parseStalePolicy(policy, &p.stale_policy) && policy_value != nullptr &&
      policy_value->type() == ParamValue::Type::kString)
    r.fail("stale_policy", "expected baseline_hold or zero, got '" + policy + "'");
  p.queue_size = readCount(r, "queue_size", p.queue_size, 0, 100000000);
  p.stale_timeout = r.getDouble("stale_timeout", p.stale_timeout);
  requireRange(r, "stale_timeout", p.stale_timeout, 0.0, 1e6, true);
  p.clock = readClockMode(r, tree, "clock", ClockMode::kRealtime);
  p.diagnostic_period = r.getDouble("diagnostic_period", p.diagnostic_period);
  requireRange(r, "diagnostic_period", p.diagnostic_period, 0.0, 3600.0, true);
  p.rt_priority = readCount(r, "rt_priority", p.rt_priority, 0, 99);
  p.cpu_affinity = readCount(r, "cpu_affinity", p.cpu_affinity, -1, 1023);
  p.accept_from = readCallerList(r, tree, "accept_from");
  // (~stale_policy was read above but missing here, so setting it was refused as unknown.)
  rejectUnknownTopLevel(
      tree, r,
      {"plant", "controller", "scenario", "weights_in", "weights_out", "save_every_episode",
       "min_command_subscribers", "min_status_subscribers", "start_timeout", "truth_buffer",
       "queue_size", "stale_policy", "stale_timeout", "clock", "diagnostic_period", "rt_priority",
       "cpu_affinity", "accept_from",
       // written by the dynamic_reconfigure server (~reconfigure/*), never read
       "reconfigure"});

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
