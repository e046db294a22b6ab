#include "preadaptive_mrac/io/yaml_params.hpp"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
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
    return ParamValue::makeDouble(std::numeric_limits<double>::quiet_NaN()).withText(s);
  if (s == ".inf" || s == ".Inf" || s == "+.inf" || s == "inf" || s == "+inf")
    return ParamValue::makeDouble(std::numeric_limits<double>::infinity()).withText(s);
  if (s == "-.inf" || s == "-.Inf" || s == "-inf")
    return ParamValue::makeDouble(-std::numeric_limits<double>::infinity()).withText(s);
  {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(s.c_str(), &end, 10);
    if (end != s.c_str() && *end == '\0' && errno == 0) return ParamValue::makeInt(v).withText(s);
  }
  {
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (end != s.c_str() && *end == '\0') return ParamValue::makeDouble(v).withText(s);
  }
  return ParamValue::makeString(s);
}

std::string childPath(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

// Walks the document as the tree will be built (each alias expanded where it is used) and
// counts its nodes and depth, before the tree allocates anything: a few hundred bytes of
// aliases nesting aliases expand to billions of nodes. Stops at the first limit exceeded, so
// its time is bounded by the limits, not by the expansion.
void checkSize(const YAML::Node& n, const std::string& path, int depth, std::size_t* count) {
  if (++*count > kMaxYamlNodes)
    throw FileError((path.empty() ? std::string("the document") : path) + ": more than " +
                    std::to_string(kMaxYamlNodes) +
                    " values once YAML aliases (*name) are expanded: an alias bomb or far "
                    "too large a configuration");
  if (depth > kMaxYamlDepth)
    throw FileError(path + ": nested deeper than " + std::to_string(kMaxYamlDepth) + " levels");
  if (n.IsSequence()) {
    std::size_t i = 0;
    for (const auto& c : n) checkSize(c, childPath(path, std::to_string(i++)), depth + 1, count);
  } else if (n.IsMap()) {
    for (const auto& kv : n) {
      const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : std::string("?");
      checkSize(kv.second, childPath(path, key), depth + 1, count);
    }
  }
}

ParamValue toParam(const YAML::Node& n, const std::string& path) {
  switch (n.Type()) {
    case YAML::NodeType::Null:
    case YAML::NodeType::Undefined:
      return ParamValue();
    case YAML::NodeType::Scalar:
      return scalarToParam(n);
    case YAML::NodeType::Sequence: {
      std::vector<ParamValue> items;
      items.reserve(n.size());
      for (const auto& c : n)
        items.push_back(toParam(c, childPath(path, std::to_string(items.size()))));
      return ParamValue::makeList(std::move(items));
    }
    case YAML::NodeType::Map: {
      ParamValue m = ParamValue::makeMap();
      std::map<std::string, int> lines;  // key -> its line, to name both lines of a repeat
      for (const auto& kv : n) {
        const int line = kv.first.Mark().line + 1;
        // Keys must be plain names: a list or map as a key ("? [a, b]: 1") has no parameter path.
        if (!kv.first.IsScalar())
          throw FileError("line " + std::to_string(line) + ": " +
                          (path.empty() ? std::string() : path + ": ") +
                          "a map key must be a plain name, not a list or map");
        const std::string& key = kv.first.Scalar();
        const auto seen = lines.emplace(key, line);
        // yaml-cpp keeps both entries of a repeated key; one of them would be dropped unseen.
        if (!seen.second)
          throw FileError(childPath(path, key) + ": duplicate key (lines " +
                          std::to_string(seen.first->second) + " and " + std::to_string(line) +
                          ")");
        m.map()[key] = toParam(kv.second, childPath(path, key));
      }
      return m;
    }
  }
  return ParamValue();
}

// The one conversion of a loaded document (a file or a --set value): bounded, then built.
ParamValue convert(const YAML::Node& n, const std::string& path) {
  std::size_t count = 0;
  checkSize(n, path, 0, &count);
  return toParam(n, path);
}

}  // namespace

ParamValue parseYaml(const std::string& text, const std::string& origin) {
  if (text.size() > kMaxYamlBytes)
    throw FileError(origin + ": " + std::to_string(text.size()) + " bytes, more than the " +
                    std::to_string(kMaxYamlBytes) + " a configuration may have");
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
    return root.IsNull() ? ParamValue::makeMap() : convert(root, "");
  } catch (const FileError& e) {
    throw FileError(origin + ": " + e.what());
  } catch (const YAML::Exception& e) {
    throw FileError(origin + ": malformed YAML: " + e.msg);
  }
}

ParamValue loadYamlFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path + ": cannot open file (" + std::string(std::strerror(errno)) + ")");
  // Read at most one byte past the limit: a huge file (or /dev/zero) is refused unread.
  std::string text(kMaxYamlBytes + 1, '\0');
  in.read(&text[0], static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kMaxYamlBytes)
    throw FileError(path + ": more than " + std::to_string(kMaxYamlBytes) +
                    " bytes, the most a configuration file may have");
  return parseYaml(text, path);
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
    tree->setPath(key, convert(n, key));
  } catch (const FileError& e) {
    throw FileError("--set " + key + ": " + e.what());
  } catch (const YAML::Exception& e) {
    throw FileError("--set " + key + ": malformed value '" + value + "': " + e.msg);
  } catch (const std::out_of_range& e) {  // a list index past the list's end
    throw FileError("--set " + std::string(e.what()));
  }
}

}  // namespace preadaptive_mrac
