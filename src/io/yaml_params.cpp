#include "preadaptive_mrac/io/yaml_params.hpp"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

namespace preadaptive_mrac {

namespace {

ParamValue scalarToParam(const YAML::Node& n) {
  const std::string& s = n.Scalar();
  if (n.Tag() == "!") return ParamValue::makeString(s);  // quoted: always a string
  if (s == "true" || s == "True" || s == "TRUE") return ParamValue::makeBool(true);
  if (s == "false" || s == "False" || s == "FALSE") return ParamValue::makeBool(false);
  if (s == "~" || s == "null" || s == "Null" || s == "NULL" || s.empty()) return ParamValue();
  if (s == ".nan" || s == ".NaN" || s == ".NAN" || s == "nan" || s == "NaN")
    return ParamValue::makeDouble(std::numeric_limits<double>::quiet_NaN());
  if (s == ".inf" || s == ".Inf" || s == "+.inf" || s == "inf" || s == "+inf")
    return ParamValue::makeDouble(std::numeric_limits<double>::infinity());
  if (s == "-.inf" || s == "-.Inf" || s == "-inf")
    return ParamValue::makeDouble(-std::numeric_limits<double>::infinity());
  {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(s.c_str(), &end, 10);
    if (end != s.c_str() && *end == '\0' && errno == 0) return ParamValue::makeInt(v);
  }
  {
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (end != s.c_str() && *end == '\0') return ParamValue::makeDouble(v);
  }
  return ParamValue::makeString(s);
}

ParamValue toParam(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Null:
    case YAML::NodeType::Undefined:
      return ParamValue();
    case YAML::NodeType::Scalar:
      return scalarToParam(n);
    case YAML::NodeType::Sequence: {
      std::vector<ParamValue> items;
      for (const auto& c : n) items.push_back(toParam(c));
      return ParamValue::makeList(std::move(items));
    }
    case YAML::NodeType::Map: {
      ParamValue m = ParamValue::makeMap();
      for (const auto& kv : n) {
        // Keys must be plain names: a list or map as a key ("? [a, b]: 1") has no parameter path.
        if (!kv.first.IsScalar())
          throw FileError("line " + std::to_string(kv.first.Mark().line + 1) +
                          ": a map key must be a plain name, not a list or map");
        m.map()[kv.first.Scalar()] = toParam(kv.second);
      }
      return m;
    }
  }
  return ParamValue();
}

}  // namespace

ParamValue parseYaml(const std::string& text, const std::string& origin) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw FileError(origin + ": malformed YAML at line " + std::to_string(e.mark.line + 1) +
                    ", column " + std::to_string(e.mark.column + 1) + ": " + e.msg);
  }
  if (!root.IsMap() && !root.IsNull())
    throw FileError(origin + ": expected a YAML map at the top level");
  try {
    return root.IsNull() ? ParamValue::makeMap() : toParam(root);
  } catch (const FileError& e) {
    throw FileError(origin + ": " + e.what());
  } catch (const YAML::Exception& e) {
    throw FileError(origin + ": malformed YAML: " + e.msg);
  }
}

ParamValue loadYamlFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw FileError(path + ": cannot open file (" + std::string(std::strerror(errno)) + ")");
  std::stringstream ss;
  ss << in.rdbuf();
  return parseYaml(ss.str(), path);
}

void applyOverride(ParamValue* tree, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw FileError("--set '" + assignment +
                    "': expected key=value, e.g. controller.attention.c_e=0.01");
  const std::string key = assignment.substr(0, eq);
  const std::string value = assignment.substr(eq + 1);
  YAML::Node n;
  try {
    n = YAML::Load(value);
  } catch (const YAML::Exception& e) {
    throw FileError("--set " + key + ": malformed value '" + value + "': " + e.msg);
  }
  try {
    tree->setPath(key, toParam(n));
  } catch (const FileError& e) {
    throw FileError("--set " + key + ": " + e.what());
  } catch (const YAML::Exception& e) {
    throw FileError("--set " + key + ": malformed value '" + value + "': " + e.msg);
  }
}

}  // namespace preadaptive_mrac
