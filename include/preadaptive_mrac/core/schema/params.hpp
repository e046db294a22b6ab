#pragma once
/// \file params.hpp
/// \brief A small parameter tree (what YAML and the ROS parameter server both hold) and a
/// reader that collects every problem at once, naming each key by its full name.
///
/// The core never parses YAML or talks to a parameter server: adapters (io/yaml_params,
/// ros/ros_params) turn those into a ParamValue, and the core's config readers (each
/// part's `read`, e.g. ControllerConfig::read in controller/controller_config.hpp) read from
/// it. So there is one validation path for the batch CLI and the ROS nodes.

#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

/// \brief A node of the parameter tree.
class ParamValue {
 public:
  enum class Type { kNull, kBool, kInt, kDouble, kString, kList, kMap };

  ParamValue() = default;
  static ParamValue makeBool(bool v);
  static ParamValue makeInt(std::int64_t v);
  static ParamValue makeDouble(double v);
  static ParamValue makeString(std::string v);
  static ParamValue makeList(std::vector<ParamValue> v = {});
  static ParamValue makeMap();

  Type type() const { return type_; }
  bool isNumber() const { return type_ == Type::kInt || type_ == Type::kDouble; }
  bool asBool() const { return b_; }
  std::int64_t asInt() const { return i_; }
  /// \brief Value of an int or double node.
  double asDouble() const { return type_ == Type::kInt ? static_cast<double>(i_) : d_; }
  const std::string& asString() const { return s_; }
  /// \brief This number node remembering `text`, the scalar as written (a YAML file, --set).
  ParamValue withText(std::string text) &&;
  /// \brief The text a number node was read from; empty when it was made from a value.
  const std::string& text() const { return s_; }
  const std::vector<ParamValue>& list() const { return list_; }
  std::vector<ParamValue>& list() { return list_; }
  const std::map<std::string, ParamValue>& map() const { return map_; }
  std::map<std::string, ParamValue>& map() { return map_; }

  /// \brief Child of a map node, or nullptr.
  const ParamValue* find(const std::string& key) const;
  /// \brief Child of a map node, created (as a map) if absent; this node becomes a map.
  ParamValue& child(const std::string& key);
  /// \brief Node at a dotted path ("controller.attention.c_e"; a number indexes a list:
  /// "scenario.theta.0.until"), or nullptr.
  const ParamValue* findPath(const std::string& dotted) const;
  /// \brief Set the node at a dotted path, creating maps on the way. Throws std::out_of_range
  /// (naming the key) for a list index past the end of its list.
  void setPath(const std::string& dotted, ParamValue v);
  /// \brief Merge another map into this one; keys of `other` win, maps merge recursively.
  void merge(const ParamValue& other);
  /// \brief Short text of the value, for messages ("0.005", "[1, 2]", "a map").
  std::string describe() const;
  static const char* typeName(Type t);

 private:
  /// \brief A node of `type` holding v in `member` (the make* functions).
  template <class T>
  static ParamValue make(Type type, T ParamValue::*member, T v);
  Type type_ = Type::kNull;
  bool b_ = false;
  std::int64_t i_ = 0;
  double d_ = 0.0;
  std::string s_;  ///< a string node's value; a number node's text as written (withText)
  std::vector<ParamValue> list_;
  std::map<std::string, ParamValue> map_;
};

/// \brief A number as a message shows it: shortest round-trip form ("0.005", "1e-09", "nan").
std::string formatNumber(double v);

/// \brief Thrown when configuration is invalid; what() holds every problem, one a line.
class ConfigError : public std::runtime_error {
 public:
  explicit ConfigError(const std::vector<std::string>& problems);
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  std::vector<std::string> problems_;
};

/// \brief How keys are named in messages: "controller.attention.c_e" for files and the CLI,
/// "/mrac_controller/controller/attention/c_e" for ROS.
struct KeyStyle {
  std::string root;  ///< prefix of every name ("" or "/node_name/")
  char separator = '.';
};

/// \brief Reads typed values from a tree, collecting problems instead of stopping at the first.
///
/// Every get*() marks the key as used; unusedUnder() then lists keys nobody read (typos).
class ParamReader {
 public:
  explicit ParamReader(const ParamValue& root, KeyStyle style = {});

  /// \brief Full name of a dotted path in this reader's key style.
  std::string name(const std::string& dotted) const;
  bool has(const std::string& dotted) const;

  /// \brief Required values: a problem is recorded when missing or of the wrong type.
  double getDouble(const std::string& dotted);
  std::int64_t getInt(const std::string& dotted);
  bool getBool(const std::string& dotted);
  std::string getString(const std::string& dotted);
  /// \brief A list of numbers; `expected_size` < 0 accepts any size >= 1.
  Eigen::VectorXd getVector(const std::string& dotted, int expected_size = -1);
  /// \brief A list of equal-length lists of numbers; negative sizes accept any.
  Eigen::MatrixXd getMatrix(const std::string& dotted, int rows = -1, int cols = -1);

  /// \brief Optional values: the default when absent, a problem when present but wrong.
  double getDouble(const std::string& dotted, double def);
  std::int64_t getInt(const std::string& dotted, std::int64_t def);
  bool getBool(const std::string& dotted, bool def);
  std::string getString(const std::string& dotted, const std::string& def);

  /// \brief Record that an optional key (or section) was absent and a default filled in;
  /// the optional getters do it themselves.
  void noteDefault(const std::string& dotted, const std::string& value);
  /// \brief "full name = value" of every default filled in, in reading order.
  const std::vector<std::string>& defaultsUsed() const { return defaults_; }

  /// \brief Size of a required list of maps (segments); -1 with a problem when absent or not a
  /// list.
  int getListSize(const std::string& dotted);

  /// \brief Mark a whole subtree as used (documentation-only keys).
  void markUsed(const std::string& dotted);
  /// \brief Keys below `dotted` (leaves and lists) that no get*() asked for.
  std::vector<std::string> unusedUnder(const std::string& dotted) const;
  /// \brief Record a problem for a key: "<full name>: <what>".
  void fail(const std::string& dotted, const std::string& what);
  /// \brief Record a problem not tied to one key.
  void failGeneral(const std::string& what);
  /// \brief Record every unused key below `dotted` as "unknown key".
  void rejectUnusedUnder(const std::string& dotted);

  const std::vector<std::string>& problems() const { return problems_; }
  bool ok() const { return problems_.empty(); }
  /// \brief True when a problem was already recorded for this key or an element of it,
  /// so a validation rule does not pile a second message on a value that was never read.
  bool failed(const std::string& dotted) const;
  /// \brief True when the key is present and nothing is wrong with it so far.
  bool usable(const std::string& dotted) const { return has(dotted) && !failed(dotted); }
  /// \brief Throw ConfigError with all problems, if any.
  void throwIfProblems() const;

 private:
  const ParamValue* lookup(const std::string& dotted, bool required);
  bool numberAt(const ParamValue& v, const std::string& dotted, double* out);
  void collectUnused(const ParamValue& v, const std::string& path,
                     std::vector<std::string>* out) const;

  const ParamValue& root_;
  KeyStyle style_;
  std::set<std::string> used_;
  std::set<std::string> failed_;
  std::vector<std::string> problems_;
  std::vector<std::string> defaults_;
};

}  // namespace preadaptive_mrac
