// params/controller.yaml with its parts' tables (robust.yaml, l1.yaml; one declaration per
// parameter) against the C++ generated from them and the reading and validation
// built on it: the defaults of every key that may be left out, the tunables, the ranges.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <string>

#include "preadaptive_mrac/core/controller/controller_config.hpp"
#include "preadaptive_mrac/core/controller/tunables.hpp"
#include "preadaptive_mrac/core/schema/params.hpp"
#include "preadaptive_mrac/io/yaml_params.hpp"

namespace preadaptive_mrac {
namespace {

ParamValue loadTable(const std::string& component) {
  // The source tree's tables (cmake/tests.cmake), wherever the config folder is found.
  return loadYamlFile(std::string(PMRAC_PARAMS_DIR) + "/" + component + ".yaml");
}

// The controller's rows with each part's table expanded under its section's key, as
// params_table.load() does for the Python side.
const std::vector<ParamValue>& rows() {
  static const std::vector<ParamValue> all = [] {
    std::vector<ParamValue> out;
    const ParamValue own = loadTable("controller");
    for (const ParamValue& row : own.find("params")->list()) {
      out.push_back(row);
      const ParamValue* part = row.find("table");
      if (part == nullptr) continue;
      const ParamValue sub_table = loadTable(part->asString());
      for (ParamValue sub : sub_table.find("params")->list()) {
        sub.setPath("key", ParamValue::makeString(row.find("key")->asString() + "." +
                                                  sub.find("key")->asString()));
        out.push_back(sub);
      }
    }
    return out;
  }();
  return all;
}

std::string field(const ParamValue& row, const char* name) {
  const ParamValue* v = row.find(name);
  return v != nullptr ? v->asString() : "";
}

// A tree with the table's defaults under `controller`: the required keys only, or all.
ParamValue defaultsTree(bool all) {
  ParamValue tree = ParamValue::makeMap();
  for (const ParamValue& row : rows()) {
    const std::string presence = field(row, "presence");
    if (field(row, "type") == "section" || row.find("default") == nullptr) continue;
    if (!all && presence != "required") continue;
    tree.setPath("controller." + field(row, "key"), *row.find("default"));
  }
  return tree;
}

std::map<std::string, double> entries(const ControllerTunables& t) {
  std::map<std::string, double> m;
  for (const TunableEntry& e : tunableEntries(t)) m[e.key] = e.value;
  return m;
}

double number(const ParamValue& v) {
  return v.type() == ParamValue::Type::kBool ? (v.asBool() ? 1.0 : 0.0) : v.asDouble();
}

TEST(ParamTable, KeysLeftOutTakeTheTablesDefaults) {
  ParamValue tree = defaultsTree(false);
  ParamReader r(tree);
  const ControllerConfig c = ControllerConfig::read(r, 3);
  ASSERT_TRUE(r.problems().empty()) << r.problems().front();
  const auto got = entries(ControllerTunables::of(c));
  int checked = 0;
  for (const ParamValue& row : rows()) {
    if (row.find("tunable") == nullptr) continue;
    const std::string key = field(row, "key");
    ASSERT_EQ(got.count(key), 1u) << key;
    EXPECT_EQ(got.at(key), number(*row.find("default"))) << key;
    ++checked;
  }
  EXPECT_GE(checked, 27);
  for (const ParamValue& row : rows()) {
    if (field(row, "key") == "adaptation.freeze_when_saturated") {
      EXPECT_EQ(c.freeze_when_saturated, row.find("default")->asBool());
    }
  }
}

TEST(ParamTable, TunablesDefaultAndKeysAreTheTables) {
  const auto def = entries(ControllerTunables());
  std::set<std::string> declared;
  for (const ParamValue& row : rows()) {
    if (row.find("tunable") == nullptr) continue;
    const std::string key = field(row, "key");
    declared.insert(key);
    ASSERT_EQ(def.count(key), 1u) << key;
    EXPECT_EQ(def.at(key), number(*row.find("default"))) << key;
  }
  std::set<std::string> glue;
  for (const auto& kv : def) glue.insert(kv.first);
  EXPECT_EQ(glue, declared);
}

bool namesKey(const std::vector<std::string>& problems, const std::string& key) {
  for (const std::string& p : problems)
    if (p.rfind(key + ":", 0) == 0) return true;
  return false;
}

TEST(ParamTable, ValidationRefusesJustOutsideEachDeclaredRange) {
  {
    ParamValue tree = defaultsTree(true);
    ParamReader r(tree);
    ControllerConfig::read(r, 3);
    ASSERT_TRUE(r.problems().empty()) << r.problems().front();
  }
  int probed = 0;
  for (const ParamValue& row : rows()) {
    const ParamValue* check = row.find("check");
    if (check == nullptr) continue;
    const std::string key = "controller." + field(row, "key");
    const bool is_int = field(row, "type") == "int";
    auto outside = [&](const char* bound, const char* open, double dir) {
      const ParamValue* b = check->find(bound);
      if (b == nullptr) return;
      const bool is_open = check->find(open) != nullptr && check->find(open)->asBool();
      const double v = is_open  ? b->asDouble()
                       : is_int ? b->asDouble() + dir
                                : std::nextafter(b->asDouble(), dir * HUGE_VAL);
      ParamValue tree = defaultsTree(true);
      tree.setPath(key, is_int ? ParamValue::makeInt(static_cast<std::int64_t>(v))
                               : ParamValue::makeDouble(v));
      ParamReader r(tree);
      ControllerConfig::read(r, 3);
      EXPECT_TRUE(namesKey(r.problems(), key)) << key << " = " << v << " passed";
      ++probed;
    };
    outside("min", "min_open", -1.0);
    outside("max", "max_open", 1.0);
  }
  EXPECT_GE(probed, 20);
}

TEST(ParamTable, StringKeysTakeNamesThatLookLikeNumbers) {
  ParamValue tree = ParamValue::makeMap();
  applyOverride(&tree, "plant.jsbsim.aircraft=737");
  ParamReader r(tree);
  EXPECT_EQ(r.getString("plant.jsbsim.aircraft"), "737");
  EXPECT_TRUE(r.ok());
  // The name is the text as written, whatever number YAML reads in it.
  for (const std::string name : {"007", "737.5", "1e3", "0x1F", "nan"}) {
    applyOverride(&tree, "plant.jsbsim.aircraft=" + name);
    ParamReader as_name(tree);
    EXPECT_EQ(as_name.getString("plant.jsbsim.aircraft"), name);
    EXPECT_TRUE(as_name.ok()) << name;
  }
  // A number for a numeric key stays the number.
  applyOverride(&tree, "plant.jsbsim.mach=0.80");
  applyOverride(&tree, "controller.seed=007");
  ParamReader numbers(tree);
  EXPECT_EQ(numbers.getDouble("plant.jsbsim.mach"), 0.8);
  EXPECT_EQ(numbers.getInt("controller.seed"), 7);
  EXPECT_TRUE(numbers.ok());
  applyOverride(&tree, "plant.jsbsim.aircraft=[7, 3]");  // not a name: still refused
  ParamReader bad(tree);
  bad.getString("plant.jsbsim.aircraft");
  EXPECT_FALSE(bad.ok());
}

}  // namespace
}  // namespace preadaptive_mrac
