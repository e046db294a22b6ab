/// \file test_node_params.cpp
/// \brief The ROS nodes' parameter readers and latency statistics, without a master: every
/// problem at once, each named by its fully resolved ROS key.

#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "preadaptive_mrac/io/weights_io.hpp"
#include "preadaptive_mrac/io/yaml_params.hpp"
#include "preadaptive_mrac/ros/latency_stats.hpp"
#include "preadaptive_mrac/ros/node_params.hpp"
#include "preadaptive_mrac/ros/tick_source.hpp"

namespace pm = preadaptive_mrac;
using pm::ros1::ClockMode;

namespace {

pm::ParamValue loadConfig(const std::vector<std::string>& files) {
  pm::ParamValue tree = pm::ParamValue::makeMap();
  for (const auto& f : files) tree.merge(pm::loadYamlFile(std::string(PMRAC_CONFIG_DIR) + "/" + f));
  return tree;
}

pm::KeyStyle style(const std::string& node) {
  pm::KeyStyle s;
  s.root = node + "/";
  s.separator = '/';
  return s;
}

/// \brief A new empty file from a mkstemp pattern (its name; "" when it could not be made).
std::string existingTempFile(std::string pattern) {
  const int fd = mkstemp(pattern.data());
  if (fd < 0) return "";
  close(fd);
  return pattern;
}

std::vector<std::string> problemsOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const pm::ConfigError& e) {
    return e.problems();
  }
  return {};
}

bool anyContains(const std::vector<std::string>& v, const std::string& needle) {
  return std::any_of(v.begin(), v.end(),
                     [&](const std::string& s) { return s.find(needle) != std::string::npos; });
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& p : v) s += p + "\n";
  return s;
}

}  // namespace

TEST(PlantNodeParams, DefaultsFromThePackageConfig) {
  const pm::ParamValue tree = loadConfig({"plant/b747.yaml", "scenarios/scenario1.yaml"});
  const auto p = pm::ros1::readPlantNodeParams(tree, style("/plant_sim"));
  EXPECT_DOUBLE_EQ(p.dt, 0.001);
  EXPECT_EQ(p.clock, ClockMode::kLockstep);
  EXPECT_DOUBLE_EQ(p.rate, 1000.0);
  EXPECT_EQ(p.world_frame, "world");
  EXPECT_EQ(p.body_frame, "body");
  EXPECT_EQ(p.velocity_frame, "velocity");
  EXPECT_EQ(p.min_state_subscribers, 1);
  EXPECT_EQ(p.run.plant.n(), 3);
  EXPECT_DOUBLE_EQ(p.run.scenario.endTime(), 60.0);
}

TEST(PlantNodeParams, NodeKeysRead) {
  pm::ParamValue tree = loadConfig({"plant/b747.yaml", "scenarios/scenario2.yaml"});
  tree.setPath("clock", pm::ParamValue::makeString("realtime"));
  tree.setPath("rate", pm::ParamValue::makeInt(500));
  tree.setPath("dt", pm::ParamValue::makeDouble(0.002));
  tree.setPath("body_frame", pm::ParamValue::makeString("rac/body"));
  const auto p = pm::ros1::readPlantNodeParams(tree, style("/rac/plant_sim"));
  EXPECT_EQ(p.clock, ClockMode::kRealtime);
  EXPECT_DOUBLE_EQ(p.rate, 500.0);
  EXPECT_DOUBLE_EQ(p.dt, 0.002);
  EXPECT_EQ(p.body_frame, "rac/body");
}

TEST(PlantNodeParams, EveryProblemAtOnceWithResolvedNames) {
  pm::ParamValue tree = loadConfig({"plant/b747.yaml", "scenarios/scenario1.yaml"});
  tree.setPath("clock", pm::ParamValue::makeString("sometimes"));
  tree.setPath("dt", pm::ParamValue::makeDouble(-0.001));
  tree.setPath("rate", pm::ParamValue::makeString("fast"));
  tree.setPath("tf_decimation", pm::ParamValue::makeInt(0));
  tree.setPath("clok", pm::ParamValue::makeString("lockstep"));
  tree.map().at("plant").map().erase("B");
  const auto probs = problemsOf([&] { pm::ros1::readPlantNodeParams(tree, style("/plant_sim")); });
  const std::string all = joined(probs);
  EXPECT_TRUE(anyContains(probs, "/plant_sim/clock")) << all;
  EXPECT_TRUE(anyContains(probs, "/plant_sim/dt")) << all;
  EXPECT_TRUE(anyContains(probs, "/plant_sim/rate")) << all;
  EXPECT_TRUE(anyContains(probs, "/plant_sim/tf_decimation")) << all;
  EXPECT_TRUE(anyContains(probs, "/plant_sim/clok: unknown parameter")) << all;
  EXPECT_TRUE(anyContains(probs, "/plant_sim/plant/B")) << all;
  EXPECT_GE(probs.size(), 6u) << all;
}

TEST(PlantNodeParams, MissingScenarioIsNamed) {
  const pm::ParamValue tree = loadConfig({"plant/b747.yaml"});
  const auto probs = problemsOf([&] { pm::ros1::readPlantNodeParams(tree, style("/p")); });
  EXPECT_TRUE(anyContains(probs, "/p/scenario")) << joined(probs);
}

TEST(ControllerNodeParams, DefaultsFromThePackageConfig) {
  const pm::ParamValue tree = loadConfig({"plant/b747.yaml", "controller/default.yaml"});
  const auto p = pm::ros1::readControllerNodeParams(tree, style("/mrac_controller"));
  EXPECT_TRUE(p.weights_in.empty());
  EXPECT_TRUE(p.weights_out.empty());
  EXPECT_TRUE(p.save_every_episode);
  EXPECT_EQ(p.min_command_subscribers, 1);
  EXPECT_EQ(p.run.controller.mode, "pa_learn");
  EXPECT_EQ(p.run.controller.hidden, 3);
  EXPECT_EQ(p.stale_policy, pm::StalePolicy::kBaselineHold);
  EXPECT_EQ(p.clock, pm::ros1::ClockMode::kRealtime);
}

// ~clock: the launch files pass their clock arg, so that in lockstep the controller measures
// staleness in the states' stamps and needs no /clock (two runs in two namespaces at once).
TEST(ControllerNodeParams, ClockLockstepOrRealtimeAndNothingElse) {
  pm::ParamValue tree = loadConfig({"plant/b747.yaml", "controller/default.yaml"});
  tree.setPath("clock", pm::ParamValue::makeString("lockstep"));
  EXPECT_EQ(pm::ros1::readControllerNodeParams(tree, style("/mrac_controller")).clock,
            pm::ros1::ClockMode::kLockstep);
  tree.setPath("clock", pm::ParamValue::makeString("sim"));
  const auto probs =
      problemsOf([&] { pm::ros1::readControllerNodeParams(tree, style("/ns/mrac_controller")); });
  // (the generated choices' message since the node rows are read from params/nodes.yaml; it
  // said "expected lockstep or realtime, got 'sim'" before)
  EXPECT_TRUE(anyContains(probs,
                          "/ns/mrac_controller/clock: expected one of lockstep, realtime, "
                          "got 'sim'"))
      << joined(probs);
}

TEST(ControllerNodeParams, MissingKeyWrongTypeAndUnknownTogether) {
  pm::ParamValue tree = loadConfig({"plant/b747.yaml", "controller/default.yaml"});
  tree.map().at("controller").map().at("adaptation").map().erase("gamma");
  tree.setPath("controller.lqr.R", pm::ParamValue::makeString("one"));
  tree.setPath("min_command_subscribers", pm::ParamValue::makeInt(-1));
  tree.setPath("weights_inn", pm::ParamValue::makeString("/tmp/w.yaml"));
  tree.setPath("stale_policy", pm::ParamValue::makeString("hover"));
  const auto probs =
      problemsOf([&] { pm::ros1::readControllerNodeParams(tree, style("/ns/mrac_controller")); });
  const std::string all = joined(probs);
  EXPECT_TRUE(anyContains(probs, "/ns/mrac_controller/controller/adaptation/gamma")) << all;
  EXPECT_TRUE(anyContains(probs, "/ns/mrac_controller/controller/lqr/R")) << all;
  EXPECT_TRUE(anyContains(probs, "/ns/mrac_controller/min_command_subscribers")) << all;
  EXPECT_TRUE(anyContains(probs, "/ns/mrac_controller/weights_inn: unknown parameter")) << all;
  EXPECT_TRUE(anyContains(probs, "/ns/mrac_controller/stale_policy")) << all;
}

TEST(ControllerNodeParams, NotStabilisableNamesThePlant) {
  pm::ParamValue tree = loadConfig({"plant/b747.yaml", "controller/default.yaml"});
  // A's eigenvalue 0 has the left eigenvector w = [2.18, 1, 2]; w^T B = 0 for B = [0, 2, -1].
  tree.setPath("plant.B", pm::ParamValue::makeList({pm::ParamValue::makeDouble(0.0),
                                                    pm::ParamValue::makeDouble(2.0),
                                                    pm::ParamValue::makeDouble(-1.0)}));
  const auto probs =
      problemsOf([&] { pm::ros1::readControllerNodeParams(tree, style("/mrac_controller")); });
  EXPECT_TRUE(anyContains(probs, "/mrac_controller/plant/A")) << joined(probs);
  EXPECT_TRUE(anyContains(probs, "not_stabilizable")) << joined(probs);
}

TEST(ControllerNodeParams, WeightsInCheckedWithTheOtherProblems) {
  pm::ParamValue tree = loadConfig({"plant/b747.yaml", "controller/default.yaml"});
  tree.setPath("weights_in", pm::ParamValue::makeString("/nonexistent/dir/w.yaml"));
  auto probs =
      problemsOf([&] { pm::ros1::readControllerNodeParams(tree, style("/mrac_controller")); });
  EXPECT_TRUE(anyContains(probs, "/mrac_controller/weights_in")) << joined(probs);

  // A readable file of the wrong size is refused too; one of the right size is accepted.
  const std::string path = std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") +
                           "/pmrac_node_params_w_" + std::to_string(::getpid()) + ".yaml";
  pm::PreadaptNetwork wrong(4, 3, 1, 1.0);
  pm::saveWeights(path, wrong.state());
  tree.setPath("weights_in", pm::ParamValue::makeString(path));
  probs = problemsOf([&] { pm::ros1::readControllerNodeParams(tree, style("/mrac_controller")); });
  EXPECT_TRUE(anyContains(probs, "/mrac_controller/weights_in")) << joined(probs);
  pm::PreadaptNetwork right(3, 3, 7, 1.0);
  pm::saveWeights(path, right.state());
  const auto p = pm::ros1::readControllerNodeParams(tree, style("/mrac_controller"));
  EXPECT_EQ(p.weights_in, path);
  std::remove(path.c_str());
}

// the safety keys are read, range-checked and known (~stale_policy used to be refused
// as an unknown parameter although the reader read it).
TEST(ControllerNodeParams, StaleKeysReadAndKnown) {
  pm::ParamValue tree = loadConfig({"plant/b747.yaml", "controller/default.yaml"});
  tree.setPath("stale_policy", pm::ParamValue::makeString("zero"));
  tree.setPath("stale_timeout", pm::ParamValue::makeDouble(0.2));
  tree.setPath("diagnostic_period", pm::ParamValue::makeDouble(0.5));
  const auto p = pm::ros1::readControllerNodeParams(tree, style("/mrac_controller"));
  EXPECT_EQ(p.stale_policy, pm::StalePolicy::kZero);
  EXPECT_DOUBLE_EQ(p.stale_timeout, 0.2);
  EXPECT_DOUBLE_EQ(p.diagnostic_period, 0.5);
  tree.setPath("stale_timeout", pm::ParamValue::makeDouble(0.0));
  const auto probs =
      problemsOf([&] { pm::ros1::readControllerNodeParams(tree, style("/mrac_controller")); });
  EXPECT_TRUE(anyContains(probs, "/mrac_controller/stale_timeout")) << joined(probs);
  EXPECT_FALSE(anyContains(probs, "unknown parameter")) << joined(probs);
  // The table's names and nothing else (the generated parser; core's hand-written twin,
  // parseStalePolicy, is gone).
  pm::StalePolicy sp = pm::StalePolicy::kZero;
  EXPECT_TRUE(pm::parseChoice("baseline_hold", &sp));
  EXPECT_EQ(sp, pm::StalePolicy::kBaselineHold);
  EXPECT_FALSE(pm::parseChoice("hold", &sp));
  EXPECT_STREQ(pm::choiceName(pm::StalePolicy::kZero), "zero");
  tree.setPath("stale_policy", pm::ParamValue::makeString("hold"));
  EXPECT_TRUE(anyContains(
      problemsOf([&] { pm::ros1::readControllerNodeParams(tree, style("/mrac_controller")); }),
      "/mrac_controller/stale_policy: expected one of baseline_hold, zero, got 'hold'"));
}

TEST(PlantNodeParams, CommandTimeoutReadAndChecked) {
  pm::ParamValue tree = loadConfig({"plant/b747.yaml", "scenarios/scenario1.yaml"});
  EXPECT_DOUBLE_EQ(pm::ros1::readPlantNodeParams(tree, style("/plant_sim")).cmd_timeout, 0.05);
  tree.setPath("cmd_timeout", pm::ParamValue::makeDouble(-1.0));
  tree.setPath("diagnostic_period", pm::ParamValue::makeDouble(0.0));
  const auto probs = problemsOf([&] { pm::ros1::readPlantNodeParams(tree, style("/plant_sim")); });
  EXPECT_TRUE(anyContains(probs, "/plant_sim/cmd_timeout")) << joined(probs);
  EXPECT_TRUE(anyContains(probs, "/plant_sim/diagnostic_period")) << joined(probs);
}

// params/nodes.yaml's rows of each node: left out, every key takes the row's default
// (and is listed as filled); just outside each declared range it is refused naming the key,
// at the bound it is taken.
pm::ParamValue nodeRowsOf(const std::string& node) {
  const pm::ParamValue table = pm::loadYamlFile(std::string(PMRAC_PARAMS_DIR) + "/nodes.yaml");
  pm::ParamValue out = pm::ParamValue::makeList();
  for (const pm::ParamValue& row : table.find("params")->list()) {
    for (const pm::ParamValue& n : row.find("nodes")->list())
      if (n.asString() == node) out.list().push_back(row);
  }
  return out;
}

// The types a recorder may subscribe with (bag_recorder.cpp passes the message traits').
const std::vector<std::string> kRecorderTypes = {"", "preadaptive_mrac/PlantState",
                                                 "tf2_msgs/TFMessage"};

// The least a recorder needs: one topic and a bag.
pm::ParamValue recorderTree() {
  pm::ParamValue t = pm::ParamValue::makeMap();
  t.setPath("topics", pm::ParamValue::makeList({pm::ParamValue::makeString("plant/state")}));
  t.setPath("output", pm::ParamValue::makeString("/tmp/x.bag"));
  return t;
}

std::vector<std::string> nodeDefaults(const std::string& node, const pm::ParamValue& tree) {
  if (node == "plant_sim_node")
    return pm::ros1::readPlantNodeParams(tree, style("/n")).defaults_used;
  if (node == "bag_recorder_node")
    return pm::ros1::readBagRecorderParams(tree, style("/n"), kRecorderTypes).defaults_used;
  return pm::ros1::readControllerNodeParams(tree, style("/n")).defaults_used;
}

std::vector<std::string> nodeProblems(const std::string& node, const pm::ParamValue& tree) {
  return problemsOf([&] { nodeDefaults(node, tree); });
}

TEST(NodeTable, DefaultsAndRangesAreTheTablesRows) {
  const std::map<std::string, std::vector<std::string>> configs = {
      {"plant_sim_node", {"plant/b747.yaml", "scenarios/scenario1.yaml"}},
      {"mrac_controller_node", {"plant/b747.yaml", "controller/default.yaml"}},
      {"bag_recorder_node", {}}};
  int checked = 0;
  for (const auto& nc : configs) {
    const pm::ParamValue base = nc.second.empty() ? recorderTree() : loadConfig(nc.second);
    const pm::ParamValue rows = nodeRowsOf(nc.first);
    ASSERT_GE(rows.list().size(), 8u) << nc.first;
    const std::vector<std::string> defaults = nodeDefaults(nc.first, base);
    for (const pm::ParamValue& row : rows.list()) {
      const std::string key = row.find("key")->asString();
      // (lists read by hand; ~output, ~output_prefix: one of them is always left out)
      const pm::ParamValue* read = row.find("read");
      if (read != nullptr && read->asString() == "custom") continue;
      if (row.find("presence")->asString() == "optional_unnoted") continue;
      const pm::ParamValue& def = *row.find("default");
      const std::string type = row.find("type")->asString();
      std::string shown = def.describe();
      if (type == "string") shown = "'" + def.asString() + "'";
      if (type == "double") shown = pm::formatNumber(def.asDouble());
      EXPECT_TRUE(anyContains(defaults, "/n/" + key + " = " + shown + ""))
          << nc.first << " " << key << " " << joined(defaults);
      const pm::ParamValue* check = row.find("check");
      if (check == nullptr) continue;
      for (const char* end : {"min", "max"}) {
        const pm::ParamValue* bound = check->find(end);
        if (bound == nullptr) continue;
        const bool lower = std::string(end) == "min";
        const pm::ParamValue* open = check->find(lower ? "min_open" : "max_open");
        const double b = bound->asDouble();
        const double outside = type == "int"
                                   ? (lower ? b - 1 : b + 1)
                                   : (lower ? std::nextafter(b, -1e300) : std::nextafter(b, 1e300));
        auto value = [&](double v) {
          return type == "int" ? pm::ParamValue::makeInt(static_cast<std::int64_t>(v))
                               : pm::ParamValue::makeDouble(v);
        };
        pm::ParamValue tree = base;
        tree.setPath(key, value(outside));
        EXPECT_TRUE(anyContains(nodeProblems(nc.first, tree), "/n/" + key + ": must be"))
            << nc.first << " " << key << " = " << outside;
        if (open != nullptr && open->asBool()) continue;
        tree.setPath(key, value(b));
        EXPECT_FALSE(anyContains(nodeProblems(nc.first, tree), "/n/" + key + ":"))
            << nc.first << " " << key << " = " << b;
        ++checked;
      }
    }
  }
  EXPECT_GE(checked, 36);
}

// bag_recorder_node: its scalars from the table, the lists by hand, every problem at
// once naming its key; before, a negative ~split_size_mb was refused but a typo (~chunk_size)
// or a string where a number belongs passed silently with the default.
TEST(BagRecorderParams, DefaultsAndListsRead) {
  pm::ParamValue t = recorderTree();
  t.setPath("types", pm::ParamValue::makeList({pm::ParamValue::makeString("tf2_msgs/TFMessage")}));
  const auto p = pm::ros1::readBagRecorderParams(t, style("/rec"), kRecorderTypes);
  EXPECT_EQ(p.topics, std::vector<std::string>{"plant/state"});
  EXPECT_EQ(p.types, std::vector<std::string>{"tf2_msgs/TFMessage"});
  EXPECT_EQ(p.output, "/tmp/x.bag");
  EXPECT_EQ(p.output_prefix, "");
  EXPECT_EQ(p.progress_every, 100);
  EXPECT_EQ(p.chunk_size_kb, 768);
  EXPECT_EQ(pm::ros1::defaultsLine(p.defaults_used),
            "optional keys filled with defaults: /rec/progress_every = 100, "
            "/rec/split_size_mb = 0, /rec/split_duration = 0, /rec/chunk_size_kb = 768, "
            "/rec/accept_from = [] (any publisher)");
}

TEST(BagRecorderParams, EveryProblemAtOnceNamingTheKey) {
  pm::ParamValue t = pm::ParamValue::makeMap();
  t.setPath("split_size_mb", pm::ParamValue::makeDouble(-1.0));
  t.setPath("split_duration", pm::ParamValue::makeDouble(2e7));
  t.setPath("chunk_size_kb", pm::ParamValue::makeInt(0));
  t.setPath("progress_every", pm::ParamValue::makeString("ten"));
  t.setPath("chunk_size", pm::ParamValue::makeInt(16));
  t.setPath("types", pm::ParamValue::makeList({pm::ParamValue::makeString("std_msgs/String")}));
  const auto probs =
      problemsOf([&] { pm::ros1::readBagRecorderParams(t, style("/rec"), kRecorderTypes); });
  for (const char* want : {"/rec/split_size_mb: must be", "/rec/split_duration: must be",
                           "/rec/chunk_size_kb: must be", "/rec/progress_every: expected",
                           "/rec/chunk_size: unknown parameter",
                           "/rec/topics: missing: expected a non-empty list of topic names",
                           "/rec/types/0: 'std_msgs/String' is not one of this package's messages",
                           "/rec/output: set ~output or ~output_prefix"})
    EXPECT_TRUE(anyContains(probs, want)) << want << "\n" << joined(probs);
  EXPECT_EQ(probs.size(), 8u) << joined(probs);

  pm::ParamValue u = recorderTree();
  u.setPath("topics", pm::ParamValue::makeList(
                          {pm::ParamValue::makeString("a"), pm::ParamValue::makeInt(3)}));
  u.setPath("types", pm::ParamValue::makeList({pm::ParamValue::makeString("")}));
  const auto p2 =
      problemsOf([&] { pm::ros1::readBagRecorderParams(u, style("/rec"), kRecorderTypes); });
  EXPECT_TRUE(anyContains(p2, "/rec/topics/1: expected a topic name (string), got int 3"))
      << joined(p2);
  u.setPath("topics", pm::ParamValue::makeList({}));
  EXPECT_TRUE(anyContains(
      problemsOf([&] { pm::ros1::readBagRecorderParams(u, style("/rec"), kRecorderTypes); }),
      "/rec/topics: expected a non-empty list of topic names, got []"));
  u = recorderTree();
  u.setPath("types", pm::ParamValue::makeList(
                         {pm::ParamValue::makeString(""), pm::ParamValue::makeString("")}));
  EXPECT_TRUE(anyContains(
      problemsOf([&] { pm::ros1::readBagRecorderParams(u, style("/rec"), kRecorderTypes); }),
      "/rec/types: expected a list of 1 type names, one per ~topics entry"));
}

// run_monitor_node: ~state_topics, and nothing else (a typo is refused, it was ignored).
TEST(RunMonitorParams, StateTopicsRequiredAndUnknownKeysRefused) {
  pm::ParamValue t = pm::ParamValue::makeMap();
  t.setPath("state_topics",
            pm::ParamValue::makeList({pm::ParamValue::makeString("rac/plant/state"),
                                      pm::ParamValue::makeString("pa/plant/state")}));
  const auto p = pm::ros1::readRunMonitorParams(t, style("/mon"));
  EXPECT_EQ(p.state_topics, (std::vector<std::string>{"rac/plant/state", "pa/plant/state"}));
  // The only optional key, ~accept_from, is absent: its default (any publisher) is named.
  EXPECT_EQ(p.defaults_used.size(), 1u) << joined(p.defaults_used);
  EXPECT_TRUE(anyContains(p.defaults_used, "/mon/accept_from")) << joined(p.defaults_used);
  t.setPath("state_topic", pm::ParamValue::makeString("x"));
  t.setPath("state_topics", pm::ParamValue::makeString("rac/plant/state"));
  const auto probs = problemsOf([&] { pm::ros1::readRunMonitorParams(t, style("/mon")); });
  EXPECT_TRUE(anyContains(probs, "/mon/state_topic: unknown parameter")) << joined(probs);
  EXPECT_TRUE(anyContains(probs,
                          "/mon/state_topics: expected a non-empty list of PlantState topic "
                          "names, got string"))
      << joined(probs);
  EXPECT_EQ(probs.size(), 2u) << joined(probs);
  EXPECT_TRUE(anyContains(
      problemsOf([&] { pm::ros1::readRunMonitorParams(pm::ParamValue::makeMap(), style("/m")); }),
      "/m/state_topics: missing"));
}

// An int beyond 32 bits is refused, not wrapped into the range (2^32 + 5 would read as 5).
TEST(NodeTable, IntBeyondThirtyTwoBitsIsRefusedNotWrapped) {
  pm::ParamValue tree = loadConfig({"plant/b747.yaml", "scenarios/scenario1.yaml"});
  tree.setPath("queue_size", pm::ParamValue::makeInt(4294967301LL));
  const auto probs = problemsOf([&] { pm::ros1::readPlantNodeParams(tree, style("/plant_sim")); });
  EXPECT_TRUE(anyContains(probs, "/plant_sim/queue_size: must fit a 32-bit int, got 4294967301"))
      << joined(probs);
}

// a short start-up timeout by default (a launch with a dead controller must end
// within seconds, not a minute) and ~linger (compare.launch marks its plants required).
TEST(PlantNodeParams, StartTimeoutAndLinger) {
  pm::ParamValue tree = loadConfig({"plant/b747.yaml", "scenarios/scenario1.yaml"});
  const auto d = pm::ros1::readPlantNodeParams(tree, style("/plant_sim"));
  EXPECT_DOUBLE_EQ(d.start_timeout, 15.0);
  EXPECT_FALSE(d.linger);
  tree.setPath("linger", pm::ParamValue::makeBool(true));
  tree.setPath("start_timeout", pm::ParamValue::makeDouble(3.0));
  const auto p = pm::ros1::readPlantNodeParams(tree, style("/plant_sim"));
  EXPECT_TRUE(p.linger);
  EXPECT_DOUBLE_EQ(p.start_timeout, 3.0);
  tree.setPath("linger", pm::ParamValue::makeString("yes"));
  tree.setPath("start_timeout", pm::ParamValue::makeDouble(-1.0));
  const auto probs = problemsOf([&] { pm::ros1::readPlantNodeParams(tree, style("/plant_sim")); });
  EXPECT_TRUE(anyContains(probs, "/plant_sim/linger")) << joined(probs);
  EXPECT_TRUE(anyContains(probs, "/plant_sim/start_timeout")) << joined(probs);
  EXPECT_FALSE(anyContains(probs, "unknown parameter")) << joined(probs);
  pm::ParamValue ctl = loadConfig({"plant/b747.yaml", "controller/default.yaml"});
  EXPECT_DOUBLE_EQ(pm::ros1::readControllerNodeParams(ctl, style("/mrac_controller")).start_timeout,
                   15.0);
}

TEST(LatencyStats, NearestRankPercentiles) {
  std::vector<double> v;
  for (int i = 100; i >= 1; --i) v.push_back(static_cast<double>(i));
  const auto s = pm::ros1::summarizeLatency(v);
  EXPECT_EQ(s.count, 100u);
  EXPECT_DOUBLE_EQ(s.p50_us, 50.0);
  EXPECT_DOUBLE_EQ(s.p99_us, 99.0);
  EXPECT_DOUBLE_EQ(s.max_us, 100.0);
  EXPECT_DOUBLE_EQ(s.mean_us, 50.5);
  const auto one = pm::ros1::summarizeLatency({7.0});
  EXPECT_DOUBLE_EQ(one.p50_us, 7.0);
  EXPECT_DOUBLE_EQ(one.p99_us, 7.0);
  const auto none = pm::ros1::summarizeLatency({});
  EXPECT_EQ(none.count, 0u);
  EXPECT_DOUBLE_EQ(none.max_us, 0.0);
}

TEST(PlantNodeParams, LatencyReportNeverReplacesAFile) {
  pm::ParamValue tree = loadConfig({"plant/b747.yaml", "scenarios/scenario1.yaml"});
  const std::string path = existingTempFile("/tmp/pmrac_latency_report_XXXXXX");
  ASSERT_FALSE(path.empty());
  tree.setPath("latency_report", pm::ParamValue::makeString(path));
  const auto probs = problemsOf([&] { pm::ros1::readPlantNodeParams(tree, style("/plant_sim")); });
  std::remove(path.c_str());
  EXPECT_TRUE(anyContains(probs, "/plant_sim/latency_report")) << joined(probs);
  EXPECT_TRUE(anyContains(probs, "exists: not replaced")) << joined(probs);
  EXPECT_EQ(pm::ros1::readPlantNodeParams(tree, style("/plant_sim")).latency_report, path);
}

TEST(PlantNodeParams, JsbsimExecutableIsNeverAParameter) {
  pm::ParamValue tree = loadConfig({"plant/b747.yaml", "scenarios/scenario1.yaml"});
  EXPECT_TRUE(
      problemsOf([&] { pm::ros1::readPlantNodeParams(tree, style("/plant_sim")); }).empty());
  // Also empty: the key itself is refused, whatever its value.
  for (const char* value : {"/bin/true", ""}) {
    tree.setPath("plant.jsbsim.executable", pm::ParamValue::makeString(value));
    const auto probs =
        problemsOf([&] { pm::ros1::readPlantNodeParams(tree, style("/plant_sim")); });
    ASSERT_EQ(probs.size(), 1u) << joined(probs);
    EXPECT_TRUE(anyContains(probs,
                            "/plant_sim/plant/jsbsim/executable: not taken from the "
                            "parameter server"))
        << joined(probs);
    EXPECT_TRUE(anyContains(probs, "$PMRAC_JSBSIM")) << joined(probs);
  }
}

/// b747.yaml's plant on the JSBSim engine flying `aircraft` of the package's JSBSim root, with
/// an elevator unlike any aircraft's and ~elevator_from_aircraft set.
pm::ParamValue jsbsimTree(const std::string& aircraft, const std::string& second_file) {
  pm::ParamValue tree = loadConfig({"plant/b747.yaml", second_file});
  tree.setPath("plant.engine", pm::ParamValue::makeString("jsbsim"));
  tree.setPath("plant.jsbsim.root", pm::ParamValue::makeString(PMRAC_JSBSIM_ROOT));
  tree.setPath("plant.jsbsim.aircraft", pm::ParamValue::makeString(aircraft));
  tree.setPath("plant.actuator.max_deflection", pm::ParamValue::makeDouble(0.1));
  tree.setPath("plant.actuator.max_rate", pm::ParamValue::makeDouble(0.2));
  tree.setPath("elevator_from_aircraft", pm::ParamValue::makeBool(true));
  return tree;
}

TEST(NodeParams, ElevatorFromAircraftIsTheAircraftsTravelAndRateInBothNodes) {
  // the search for JSBSim comes first; its program is not run here
  setenv("PMRAC_JSBSIM", "/bin/true", 1);
  const std::string note =
      "plant.actuator from the aircraft 'navion': travel 0.4363 rad, rate 1.0472 rad/s "
      "(<actuator> 'Elevator Actuator')";
  const auto plant = pm::ros1::readPlantNodeParams(jsbsimTree("navion", "scenarios/scenario1.yaml"),
                                                   style("/plant_sim"));
  const auto ctrl = pm::ros1::readControllerNodeParams(
      jsbsimTree("navion", "controller/default.yaml"), style("/mrac_controller"));
  for (const pm::RunConfig* rc : {&plant.run, &ctrl.run}) {
    EXPECT_TRUE(rc->plant.actuator.enabled);
    EXPECT_EQ(rc->plant.actuator.max_deflection, 0.4363);
    EXPECT_EQ(rc->plant.actuator.max_rate, 1.0472);
    EXPECT_TRUE(anyContains(rc->derived, note)) << joined(rc->derived);
  }
  // off (the default): the plant file's elevator as it is
  pm::ParamValue off = jsbsimTree("navion", "scenarios/scenario1.yaml");
  off.map().erase("elevator_from_aircraft");
  const auto as_given = pm::ros1::readPlantNodeParams(off, style("/plant_sim"));
  EXPECT_FALSE(as_given.run.plant.actuator.enabled);
  EXPECT_EQ(as_given.run.plant.actuator.max_deflection, 0.1);
}

TEST(NodeParams, ElevatorFromAircraftRefusedWhereThereIsNone) {
  setenv("PMRAC_JSBSIM", "/bin/true", 1);
  const auto refusal = [](const pm::ParamValue& tree) {
    return joined(problemsOf([&] { pm::ros1::readPlantNodeParams(tree, style("/plant_sim")); }));
  };
  pm::ParamValue linear = jsbsimTree("navion", "scenarios/scenario1.yaml");
  linear.setPath("plant.engine", pm::ParamValue::makeString("linear"));
  EXPECT_NE(refusal(linear).find("/plant_sim/elevator_from_aircraft: needs plant.engine jsbsim"),
            std::string::npos)
      << refusal(linear);
  const std::string own = refusal(jsbsimTree("b747_pmrac", "scenarios/scenario1.yaml"));
  EXPECT_NE(own.find("/plant_sim/elevator_from_aircraft: the aircraft 'b747_pmrac' carries the "
                     "package's interface"),
            std::string::npos)
      << own;
  const std::string missing = refusal(jsbsimTree("737", "scenarios/scenario1.yaml"));
  EXPECT_NE(missing.find("/plant_sim/elevator_from_aircraft: cannot read the aircraft's elevator: "
                         "plant.jsbsim.aircraft: no aircraft '737'"),
            std::string::npos)
      << missing;
}

TEST(ControllerNodeParams, WeightsOutNeverReplacesAnotherRunsFile) {
  pm::ParamValue tree = loadConfig({"plant/b747.yaml", "controller/default.yaml"});
  const std::string path = existingTempFile("/tmp/pmrac_weights_out_XXXXXX");
  ASSERT_FALSE(path.empty());
  tree.setPath("weights_out", pm::ParamValue::makeString(path));
  const auto probs =
      problemsOf([&] { pm::ros1::readControllerNodeParams(tree, style("/mrac_controller")); });
  std::remove(path.c_str());
  EXPECT_TRUE(
      anyContains(probs, "/mrac_controller/weights_out: '" + path + "' exists: not replaced"))
      << joined(probs);
  // Gone: saved there as before.
  EXPECT_EQ(pm::ros1::readControllerNodeParams(tree, style("/mrac_controller")).weights_out, path);
}

TEST(LatencyStats, HistogramMatchesNearestRankInFixedMemory) {
  // Exponential-ish round trips from 5 us to 50 ms: the histogram's percentiles are the exact
  // ones within its bin width, its max and mean exact; its size does not depend on the count.
  std::mt19937_64 rng(40);
  std::exponential_distribution<double> d(1.0 / 200.0);
  std::vector<double> v;
  pm::ros1::LatencyStats h;
  const auto before = sizeof(h);
  for (int i = 0; i < 200000; ++i) {
    const double x = 5.0 + std::min(d(rng), 5e4);
    v.push_back(x);
    h.add(x);
  }
  const auto exact = pm::ros1::summarizeLatency(v);
  const auto s = h.summary();
  EXPECT_EQ(s.count, exact.count);
  EXPECT_NEAR(s.p50_us, exact.p50_us, 0.0025 * exact.p50_us);
  EXPECT_NEAR(s.p99_us, exact.p99_us, 0.0025 * exact.p99_us);
  EXPECT_DOUBLE_EQ(s.max_us, exact.max_us);
  EXPECT_NEAR(s.mean_us, exact.mean_us, 1e-9 * exact.mean_us);
  EXPECT_EQ(sizeof(h), before);
  EXPECT_LT(sizeof(h), 64u * 1024u);
  // Below 1 us (negative too: two hosts' clocks), far above the top, and non-finite samples.
  pm::ros1::LatencyStats e;
  e.add(-3.0);
  e.add(0.5);
  e.add(1e12);
  e.add(std::numeric_limits<double>::quiet_NaN());
  const auto es = e.summary();
  EXPECT_EQ(es.count, 3u);
  EXPECT_EQ(e.nonFinite(), 1u);
  EXPECT_DOUBLE_EQ(es.p50_us, 0.0);  // "below 1 us"
  EXPECT_DOUBLE_EQ(es.max_us, 1e12);
  EXPECT_DOUBLE_EQ(es.p99_us, 1e12);
  EXPECT_EQ(pm::ros1::LatencyStats().summary().count, 0u);
}

TEST(LatencyStats, ReportJson) {
  pm::ros1::RunReport r;
  r.clock = "realtime";
  r.scenario = "scenario\"1";
  r.steps = 10;
  r.total_steps = 12;
  r.wall_time_s = 0.25;
  r.stale_steps = 2;
  r.late_ticks = 3;
  r.scheduling = "normal";
  r.latency = pm::ros1::summarizeLatency({1.0, 2.0, 3.0});
  const std::string text = pm::ros1::runReportJson(r);
  EXPECT_EQ(text.find('\n'), std::string::npos);
  const auto j = nlohmann::json::parse(text);
  EXPECT_EQ(j.at("clock"), "realtime");
  EXPECT_EQ(j.at("scenario"), "scenario\"1");
  EXPECT_EQ(j.at("steps"), 10);
  EXPECT_EQ(j.at("total_steps"), 12);
  EXPECT_DOUBLE_EQ(j.at("wall_time_s").get<double>(), 0.25);
  EXPECT_EQ(j.at("stale_steps"), 2);
  EXPECT_EQ(j.at("late_ticks"), 3);
  EXPECT_EQ(j.at("completed"), false);
  EXPECT_EQ(j.at("scheduling"), "normal");
  EXPECT_DOUBLE_EQ(j.at("latency_us").at("p50").get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(j.at("latency_us").at("p99").get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(j.at("latency_us").at("max").get<double>(), 3.0);
  // launch_checked --expect-report looks for this text.
  r.completed = true;
  EXPECT_NE(pm::ros1::runReportJson(r).find("\"completed\":true"), std::string::npos);
}

TEST(TickSource, DeadlinesDoNotDriftAfterALateWakeUp) {
  pm::ros1::TickSource ticks(0.001);
  ticks.start();
  const double t0 = ticks.deadline();
  ticks.waitNext();
  EXPECT_NEAR(ticks.deadline() - t0, 0.001, 1e-9);
  // Stall for 5 periods: the next ticks are behind schedule and run at once, each reporting
  // how late it is, and the deadlines stay on the grid start + k period.
  const std::int64_t stall_until = pm::ros1::monotonicNs() + 5000000;
  while (pm::ros1::monotonicNs() < stall_until) {
  }
  const double late = ticks.waitNext();
  EXPECT_GE(late, 0.003);
  EXPECT_TRUE(ticks.late());
  EXPECT_NEAR(ticks.deadline() - t0, 0.002, 1e-9);
  for (int k = 3; k <= 10; ++k) ticks.waitNext();
  EXPECT_EQ(ticks.ticks(), 10);
  EXPECT_NEAR(ticks.deadline() - t0, 0.010, 1e-9);
  // Having waited for tick 10, the thread cannot be earlier than its deadline.
  EXPECT_GE(static_cast<double>(pm::ros1::monotonicNs()) * 1e-9, ticks.deadline() - 1e-9);
}

TEST(TickSource, SchedulingRefusalsAreWarningsNamingTheKey) {
  // Nothing asked: nothing changed, no warning.
  const auto none = pm::ros1::applyRealtimeScheduling(0, -1);
  EXPECT_FALSE(none.fifo);
  EXPECT_FALSE(none.pinned);
  EXPECT_EQ(none.warnings, "");
  EXPECT_EQ(none.describe(), "normal");
  // A CPU that does not exist: refused with a warning naming ~cpu_affinity, no exception.
  const auto bad = pm::ros1::applyRealtimeScheduling(0, 1023);
  EXPECT_FALSE(bad.pinned);
  EXPECT_NE(bad.warnings.find("~cpu_affinity 1023"), std::string::npos) << bad.warnings;
  // SCHED_FIFO: either granted (root or an rtprio limit) or a warning naming ~rt_priority.
  const auto fifo = pm::ros1::applyRealtimeScheduling(1, -1);
  if (fifo.fifo) {
    EXPECT_EQ(fifo.describe(), "SCHED_FIFO 1");
    sched_param sp{};
    sp.sched_priority = 0;
    ASSERT_EQ(pthread_setschedparam(pthread_self(), SCHED_OTHER, &sp), 0);
  } else {
    EXPECT_NE(fifo.warnings.find("~rt_priority 1"), std::string::npos) << fifo.warnings;
  }
  // A node in a process of its own: the process's other threads too, counted in the report.
  const auto whole = pm::ros1::applyRealtimeScheduling(1, -1, /*whole_process=*/true);
  if (whole.fifo) {
    EXPECT_GE(whole.others_raised, 0);
    EXPECT_NE(whole.describe().find("other thread(s) raised"), std::string::npos)
        << whole.describe();
    sched_param sp{};
    sp.sched_priority = 0;
    ASSERT_EQ(pthread_setschedparam(pthread_self(), SCHED_OTHER, &sp), 0);
  } else {
    EXPECT_EQ(whole.others_raised, -1);
  }
  EXPECT_EQ(fifo.others_raised, -1);  // not asked
}

// The process shape under load: every other thread of the process (roscpp's receiving thread
// among them) raised to SCHED_FIFO, the caller's own policy left to applyRealtimeScheduling.
TEST(TickSource, RaiseOtherThreadsRaisesTheOthersNotTheCaller) {
  EXPECT_EQ(pm::ros1::raiseOtherThreads(0), 0);  // nothing asked, nothing done
  std::mutex m;
  std::condition_variable cv;
  bool go = false;
  int seen_policy = -1;
  std::thread other([&] {
    std::unique_lock<std::mutex> lock(m);
    cv.wait(lock, [&] { return go; });
    // The kernel's policy of this thread (pthread_getschedparam may answer from glibc's cache).
    seen_policy = sched_getscheduler(0);
  });
  sched_param probe{};
  probe.sched_priority = 1;
  const bool may = pthread_setschedparam(other.native_handle(), SCHED_FIFO, &probe) == 0;
  probe.sched_priority = 0;
  pthread_setschedparam(other.native_handle(), SCHED_OTHER, &probe);
  const int raised = pm::ros1::raiseOtherThreads(1);
  {
    std::lock_guard<std::mutex> lock(m);
    go = true;
  }
  cv.notify_one();
  other.join();
  EXPECT_EQ(sched_getscheduler(0), SCHED_OTHER);  // the caller is not touched
  if (!may) GTEST_SKIP() << "SCHED_FIFO not permitted here (no CAP_SYS_NICE)";
  EXPECT_GE(raised, 1);
  EXPECT_EQ(seen_policy, SCHED_FIFO);
}

// no silent defaults: every optional key a node fills in is listed (resolved name and
// value), the node's own keys and the config sections' alike; a key that is set is not.
TEST(NodeDefaults, ControllerListsEveryFilledOptionalKey) {
  pm::ParamValue tree = loadConfig({"plant/b747.yaml", "controller/default.yaml"});
  tree.map()["controller"].map()["attention"].map().erase("hysteresis");
  tree.setPath("stale_timeout", pm::ParamValue::makeDouble(0.1));
  const auto p = pm::ros1::readControllerNodeParams(tree, style("/mrac_controller"));
  const std::string line = pm::ros1::defaultsLine(p.defaults_used);
  EXPECT_EQ(line.rfind("optional keys filled with defaults: ", 0), 0u) << line;
  EXPECT_NE(line.find("/mrac_controller/controller/attention/hysteresis = 0"), std::string::npos)
      << line;
  EXPECT_NE(line.find("/mrac_controller/stale_policy = 'baseline_hold'"), std::string::npos)
      << line;
  EXPECT_NE(line.find("/mrac_controller/queue_size = 0"), std::string::npos) << line;
  EXPECT_EQ(line.find("stale_timeout"), std::string::npos) << line;
  EXPECT_EQ(line.find("confirm_samples"), std::string::npos) << line;  // in default.yaml
  EXPECT_EQ(line.find("\n"), std::string::npos);
}

TEST(NodeDefaults, PlantListsNodeKeysAndAbsentSections) {
  pm::ParamValue tree = loadConfig({"plant/b747.yaml", "scenarios/scenario1.yaml"});
  tree.map()["plant"].map().erase("noise");
  tree.setPath("clock", pm::ParamValue::makeString("realtime"));
  const auto p = pm::ros1::readPlantNodeParams(tree, style("/plant_sim"));
  EXPECT_TRUE(anyContains(p.defaults_used, "/plant_sim/dt = 0.001")) << joined(p.defaults_used);
  EXPECT_TRUE(anyContains(p.defaults_used, "/plant_sim/plant/noise = absent"))
      << joined(p.defaults_used);
  EXPECT_FALSE(anyContains(p.defaults_used, "/plant_sim/clock =")) << joined(p.defaults_used);
  EXPECT_FALSE(anyContains(p.defaults_used, "/plant_sim/plant/actuator"))
      << joined(p.defaults_used);
}

TEST(NodeDefaults, NothingFilledSaysNone) {
  EXPECT_EQ(pm::ros1::defaultsLine({}), "optional keys filled with defaults: none");
  EXPECT_EQ(pm::ros1::defaultsLine({"/a = 1", "/b = 'x'"}),
            "optional keys filled with defaults: /a = 1, /b = 'x'");
}

// ~accept_from (PublisherGuard): a list of node names on both nodes; absent = any
// publisher (named among the defaults); every bad entry named with its resolved key.
TEST(AcceptFrom, ReadOnBothNodesAbsentMeansAnyPublisher) {
  pm::ParamValue plant = loadConfig({"plant/b747.yaml", "scenarios/scenario1.yaml"});
  auto p = pm::ros1::readPlantNodeParams(plant, style("/plant_sim"));
  EXPECT_TRUE(p.accept_from.empty());
  EXPECT_TRUE(anyContains(p.defaults_used, "/plant_sim/accept_from = [] (any publisher)"))
      << joined(p.defaults_used);
  plant.setPath("accept_from",
                pm::ParamValue::makeList({pm::ParamValue::makeString("/mrac_controller"),
                                          pm::ParamValue::makeString("pmrac_manager")}));
  p = pm::ros1::readPlantNodeParams(plant, style("/plant_sim"));
  EXPECT_EQ(p.accept_from, (std::vector<std::string>{"/mrac_controller", "pmrac_manager"}));
  EXPECT_FALSE(anyContains(p.defaults_used, "accept_from")) << joined(p.defaults_used);

  pm::ParamValue ctl = loadConfig({"plant/b747.yaml", "controller/default.yaml"});
  ctl.setPath("accept_from", pm::ParamValue::makeList({pm::ParamValue::makeString("/plant_sim")}));
  const auto c = pm::ros1::readControllerNodeParams(ctl, style("/mrac_controller"));
  EXPECT_EQ(c.accept_from, std::vector<std::string>{"/plant_sim"});
  // [] is the same as absent: any publisher.
  ctl.setPath("accept_from", pm::ParamValue::makeList({}));
  EXPECT_TRUE(
      pm::ros1::readControllerNodeParams(ctl, style("/mrac_controller")).accept_from.empty());
}

TEST(AcceptFrom, EveryBadEntryNamedWithTheOtherProblems) {
  pm::ParamValue ctl = loadConfig({"plant/b747.yaml", "controller/default.yaml"});
  ctl.setPath("accept_from",
              pm::ParamValue::makeList(
                  {pm::ParamValue::makeString("/plant_sim"), pm::ParamValue::makeInt(3),
                   pm::ParamValue::makeString("~plant"), pm::ParamValue::makeString("/a b")}));
  ctl.setPath("stale_timeout", pm::ParamValue::makeDouble(-1.0));
  const auto problems =
      problemsOf([&] { pm::ros1::readControllerNodeParams(ctl, style("/mrac_controller")); });
  EXPECT_TRUE(anyContains(
      problems, "/mrac_controller/accept_from/1: expected a node name (string), got int 3"))
      << joined(problems);
  EXPECT_TRUE(anyContains(problems, "/mrac_controller/accept_from/2: '~plant' is not a node name"))
      << joined(problems);
  EXPECT_TRUE(anyContains(problems, "/mrac_controller/accept_from/3: '/a b' is not a node name"))
      << joined(problems);
  EXPECT_TRUE(anyContains(problems, "/mrac_controller/stale_timeout")) << joined(problems);
  EXPECT_FALSE(anyContains(problems, "accept_from/0")) << joined(problems);

  pm::ParamValue plant = loadConfig({"plant/b747.yaml", "scenarios/scenario1.yaml"});
  plant.setPath("accept_from", pm::ParamValue::makeString("/mrac_controller"));
  const auto pp = problemsOf([&] { pm::ros1::readPlantNodeParams(plant, style("/plant_sim")); });
  ASSERT_EQ(pp.size(), 1u) << joined(pp);
  EXPECT_NE(pp[0].find("/plant_sim/accept_from: expected a list of node names"), std::string::npos)
      << pp[0];
}
