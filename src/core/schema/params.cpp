#include "preadaptive_mrac/core/schema/params.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace preadaptive_mrac {

namespace {
std::vector<std::string> splitDotted(const std::string& dotted) {
  std::vector<std::string> parts;
  std::string cur;
  for (char c : dotted) {
    if (c == '.') {
      parts.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  parts.push_back(cur);
  return parts;
}

// A list index in a dotted key ("theta.2"): its digits as a number, or -1 when `part` is not
// all digits; an index of more digits than any list can have reads as one past every list.
long long listIndex(const std::string& part) {
  if (part.empty() || part.find_first_not_of("0123456789") != std::string::npos) return -1;
  if (part.size() > 9) return 1000000000LL;
  return std::stoll(part);
}

std::string joinProblems(const std::vector<std::string>& problems) {
  std::string out;
  for (const auto& p : problems) {
    if (!out.empty()) out += '\n';
    out += p;
  }
  return out;
}
}  // namespace

template <class T>
ParamValue ParamValue::make(Type type, T ParamValue::*member, T v) {
  ParamValue p;
  p.type_ = type;
  p.*member = std::move(v);
  return p;
}
ParamValue ParamValue::makeBool(bool v) { return make(Type::kBool, &ParamValue::b_, v); }
ParamValue ParamValue::makeInt(std::int64_t v) { return make(Type::kInt, &ParamValue::i_, v); }
ParamValue ParamValue::makeDouble(double v) { return make(Type::kDouble, &ParamValue::d_, v); }
ParamValue ParamValue::makeString(std::string v) {
  return make(Type::kString, &ParamValue::s_, std::move(v));
}
ParamValue ParamValue::withText(std::string text) && {
  if (isNumber()) s_ = std::move(text);
  return std::move(*this);
}
ParamValue ParamValue::makeList(std::vector<ParamValue> v) {
  ParamValue p;
  p.type_ = Type::kList;
  p.list_ = std::move(v);
  return p;
}
ParamValue ParamValue::makeMap() {
  ParamValue p;
  p.type_ = Type::kMap;
  return p;
}

const ParamValue* ParamValue::find(const std::string& key) const {
  if (type_ != Type::kMap) return nullptr;
  auto it = map_.find(key);
  return it == map_.end() ? nullptr : &it->second;
}

ParamValue& ParamValue::child(const std::string& key) {
  if (type_ != Type::kMap) {
    *this = makeMap();
  }
  auto it = map_.find(key);
  if (it == map_.end()) it = map_.emplace(key, makeMap()).first;
  return it->second;
}

const ParamValue* ParamValue::findPath(const std::string& dotted) const {
  const ParamValue* cur = this;
  for (const auto& part : splitDotted(dotted)) {
    const long long idx = cur->type_ == Type::kList ? listIndex(part) : -1;
    if (idx >= 0) {
      if (static_cast<size_t>(idx) >= cur->list_.size()) return nullptr;
      cur = &cur->list_[static_cast<size_t>(idx)];
      continue;
    }
    cur = cur->find(part);
    if (cur == nullptr) return nullptr;
  }
  return cur;
}

void ParamValue::setPath(const std::string& dotted, ParamValue v) {
  ParamValue* cur = this;
  for (const auto& part : splitDotted(dotted)) {
    const long long idx = cur->type_ == Type::kList ? listIndex(part) : -1;
    if (idx >= 0) {
      // A list is not silently replaced by a map holding one entry: the index must exist.
      if (static_cast<size_t>(idx) >= cur->list_.size())
        throw std::out_of_range(
            dotted + ": index " + (part.size() > 9 ? part.substr(0, 9) + "..." : part) +
            " is past the end of the list (" + std::to_string(cur->list_.size()) + " entries)");
      cur = &cur->list_[static_cast<size_t>(idx)];
      continue;
    }
    cur = &cur->child(part);
  }
  *cur = std::move(v);
}

void ParamValue::merge(const ParamValue& other) {
  if (other.type_ != Type::kMap || type_ != Type::kMap) {
    *this = other;
    return;
  }
  for (const auto& kv : other.map_) {
    auto it = map_.find(kv.first);
    if (it == map_.end()) {
      map_.emplace(kv.first, kv.second);
    } else {
      it->second.merge(kv.second);
    }
  }
}

std::string ParamValue::describe() const {
  std::ostringstream os;
  os.precision(17);
  switch (type_) {
    case Type::kNull:
      return "null";
    case Type::kBool:
      return b_ ? "true" : "false";
    case Type::kInt:
      os << i_;
      return os.str();
    case Type::kDouble:
      os << d_;
      return os.str();
    case Type::kString:
      return "'" + s_ + "'";
    case Type::kMap:
      return "a map";
    case Type::kList: {
      os << '[';
      for (size_t i = 0; i < list_.size(); ++i) {
        if (i) os << ", ";
        if (i >= 8) {
          os << "...";
          break;
        }
        os << list_[i].describe();
      }
      os << ']';
      return os.str();
    }
  }
  return "?";
}

const char* ParamValue::typeName(Type t) {
  // In the order of the enumerators (params.hpp).
  static const char* const kNames[] = {"null", "bool", "int", "double", "string", "list", "map"};
  const auto i = static_cast<size_t>(t);
  return i < sizeof(kNames) / sizeof(kNames[0]) ? kNames[i] : "?";
}

ConfigError::ConfigError(const std::vector<std::string>& problems)
    : std::runtime_error(joinProblems(problems)), problems_(problems) {}

ParamReader::ParamReader(const ParamValue& root, KeyStyle style)
    : root_(root), style_(std::move(style)) {}

std::string ParamReader::name(const std::string& dotted) const {
  std::string out = style_.root;
  for (char c : dotted) out += (c == '.') ? style_.separator : c;
  return out;
}

bool ParamReader::has(const std::string& dotted) const { return root_.findPath(dotted) != nullptr; }

const ParamValue* ParamReader::lookup(const std::string& dotted, bool required) {
  used_.insert(dotted);
  const ParamValue* v = root_.findPath(dotted);
  if (v == nullptr && required) fail(dotted, "missing (required)");
  return v;
}

bool ParamReader::numberAt(const ParamValue& v, const std::string& dotted, double* out) {
  if (!v.isNumber()) {
    fail(dotted, std::string("expected a number, got ") + ParamValue::typeName(v.type()) + " " +
                     v.describe());
    return false;
  }
  double d = v.asDouble();
  if (!std::isfinite(d)) {
    fail(dotted, "expected a finite number, got " + v.describe());
    return false;
  }
  *out = d;
  return true;
}

double ParamReader::getDouble(const std::string& dotted) {
  const ParamValue* v = lookup(dotted, true);
  double d = 0.0;
  if (v != nullptr) numberAt(*v, dotted, &d);
  return d;
}

void ParamReader::noteDefault(const std::string& dotted, const std::string& value) {
  defaults_.push_back(name(dotted) + " = " + value);
}

double ParamReader::getDouble(const std::string& dotted, double def) {
  const ParamValue* v = lookup(dotted, false);
  if (v == nullptr) {
    noteDefault(dotted, formatNumber(def));
    return def;
  }
  double d = def;
  numberAt(*v, dotted, &d);
  return d;
}

std::int64_t ParamReader::getInt(const std::string& dotted) {
  const ParamValue* v = lookup(dotted, true);
  if (v == nullptr) return 0;
  if (v->type() != ParamValue::Type::kInt) {
    fail(dotted, std::string("expected an integer, got ") + ParamValue::typeName(v->type()) + " " +
                     v->describe());
    return 0;
  }
  return v->asInt();
}

std::int64_t ParamReader::getInt(const std::string& dotted, std::int64_t def) {
  if (!has(dotted)) {
    used_.insert(dotted);
    noteDefault(dotted, std::to_string(def));
    return def;
  }
  return getInt(dotted);
}

bool ParamReader::getBool(const std::string& dotted) {
  const ParamValue* v = lookup(dotted, true);
  if (v == nullptr) return false;
  if (v->type() != ParamValue::Type::kBool) {
    fail(dotted, std::string("expected true or false, got ") + ParamValue::typeName(v->type()) +
                     " " + v->describe());
    return false;
  }
  return v->asBool();
}

bool ParamReader::getBool(const std::string& dotted, bool def) {
  if (!has(dotted)) {
    used_.insert(dotted);
    noteDefault(dotted, def ? "true" : "false");
    return def;
  }
  return getBool(dotted);
}

std::string ParamReader::getString(const std::string& dotted) {
  const ParamValue* v = lookup(dotted, true);
  if (v == nullptr) return {};
  // A name may look like a number (an aircraft "737", "007", "1.5"): YAML reads it as one, and
  // the text as written is the name; a number made from a value (ROS, code) has only its digits.
  if (v->isNumber() && !v->text().empty()) return v->text();
  if (v->type() == ParamValue::Type::kInt) return std::to_string(v->asInt());
  if (v->type() != ParamValue::Type::kString) {
    fail(dotted, std::string("expected a string, got ") + ParamValue::typeName(v->type()) + " " +
                     v->describe());
    return {};
  }
  return v->asString();
}

std::string ParamReader::getString(const std::string& dotted, const std::string& def) {
  if (!has(dotted)) {
    used_.insert(dotted);
    noteDefault(dotted, "'" + def + "'");
    return def;
  }
  return getString(dotted);
}

Eigen::VectorXd ParamReader::getVector(const std::string& dotted, int expected_size) {
  const ParamValue* v = lookup(dotted, true);
  if (v == nullptr) return Eigen::VectorXd::Zero(expected_size > 0 ? expected_size : 0);
  if (v->type() != ParamValue::Type::kList) {
    fail(dotted, std::string("expected a list of numbers, got ") + ParamValue::typeName(v->type()) +
                     " " + v->describe());
    return Eigen::VectorXd::Zero(expected_size > 0 ? expected_size : 0);
  }
  const auto& l = v->list();
  if (expected_size >= 0 && static_cast<int>(l.size()) != expected_size) {
    fail(dotted, "expected " + std::to_string(expected_size) + " numbers, got " +
                     std::to_string(l.size()) + " " + v->describe());
    return Eigen::VectorXd::Zero(expected_size);
  }
  if (l.empty()) {
    fail(dotted, "expected a non-empty list of numbers, got []");
    return {};
  }
  Eigen::VectorXd out(static_cast<Eigen::Index>(l.size()));
  for (size_t i = 0; i < l.size(); ++i) {
    if (!numberAt(l[i], dotted + "[" + std::to_string(i) + "]", &out[static_cast<Eigen::Index>(i)]))
      out[static_cast<Eigen::Index>(i)] = 0.0;
  }
  return out;
}

Eigen::MatrixXd ParamReader::getMatrix(const std::string& dotted, int rows, int cols) {
  auto zero = [&] { return Eigen::MatrixXd::Zero(rows > 0 ? rows : 0, cols > 0 ? cols : 0); };
  const ParamValue* v = lookup(dotted, true);
  if (v == nullptr) return zero();
  if (v->type() != ParamValue::Type::kList || v->list().empty()) {
    fail(dotted, "expected a non-empty list of rows (lists of numbers), got " + v->describe());
    return zero();
  }
  const auto& l = v->list();
  if (rows >= 0 && static_cast<int>(l.size()) != rows) {
    fail(dotted, "expected " + std::to_string(rows) + " rows, got " + std::to_string(l.size()));
    return zero();
  }
  int c = -1;
  for (size_t i = 0; i < l.size(); ++i) {
    if (l[i].type() != ParamValue::Type::kList) {
      fail(dotted, "row " + std::to_string(i) + " is not a list: " + l[i].describe());
      return zero();
    }
    int ci = static_cast<int>(l[i].list().size());
    if (c < 0) c = ci;
    if (ci != c) {
      fail(dotted, "rows have different lengths (" + std::to_string(c) + " and " +
                       std::to_string(ci) + ")");
      return zero();
    }
  }
  if (cols >= 0 && c != cols) {
    fail(dotted, "expected " + std::to_string(cols) + " columns, got " + std::to_string(c));
    return zero();
  }
  Eigen::MatrixXd out(static_cast<Eigen::Index>(l.size()), c);
  for (size_t i = 0; i < l.size(); ++i)
    for (int j = 0; j < c; ++j) {
      double d = 0.0;
      numberAt(l[i].list()[static_cast<size_t>(j)],
               dotted + "[" + std::to_string(i) + "][" + std::to_string(j) + "]", &d);
      out(static_cast<Eigen::Index>(i), j) = d;
    }
  return out;
}

int ParamReader::getListSize(const std::string& dotted) {
  const ParamValue* v = lookup(dotted, true);
  if (v == nullptr) return -1;
  if (v->type() != ParamValue::Type::kList || v->list().empty()) {
    fail(dotted, "expected a non-empty list, got " + v->describe());
    return -1;
  }
  return static_cast<int>(v->list().size());
}

void ParamReader::markUsed(const std::string& dotted) { used_.insert(dotted); }

void ParamReader::collectUnused(const ParamValue& v, const std::string& path,
                                std::vector<std::string>* out) const {
  // A list of maps read entry by entry (scenario segments) is used as a list, but each entry's
  // keys are looked up one by one (even the missing ones): report the rest of those entries'
  // keys, so `untill` is named beside `until: missing`.
  if (v.type() == ParamValue::Type::kList && used_.count(path)) {
    for (size_t i = 0; i < v.list().size(); ++i) {
      const std::string entry = path + "." + std::to_string(i) + ".";
      const auto it = used_.lower_bound(entry);
      if (v.list()[i].type() == ParamValue::Type::kMap && it != used_.end() &&
          it->compare(0, entry.size(), entry) == 0)
        collectUnused(v.list()[i], entry.substr(0, entry.size() - 1), out);
    }
    return;
  }
  if (used_.count(path)) return;
  if (v.type() == ParamValue::Type::kMap && !v.map().empty()) {
    for (const auto& kv : v.map())
      collectUnused(kv.second, path.empty() ? kv.first : path + "." + kv.first, out);
  } else {
    out->push_back(path);
  }
}

std::vector<std::string> ParamReader::unusedUnder(const std::string& dotted) const {
  std::vector<std::string> out;
  const ParamValue* v = dotted.empty() ? &root_ : root_.findPath(dotted);
  if (v == nullptr || used_.count(dotted)) return out;
  if (v->type() == ParamValue::Type::kMap) {
    for (const auto& kv : v->map())
      collectUnused(kv.second, dotted.empty() ? kv.first : dotted + "." + kv.first, &out);
  }
  return out;
}

void ParamReader::fail(const std::string& dotted, const std::string& what) {
  failed_.insert(dotted);
  problems_.push_back(name(dotted) + ": " + what);
}

bool ParamReader::failed(const std::string& dotted) const {
  for (const auto& f : failed_) {
    if (f.compare(0, dotted.size(), dotted) != 0) continue;
    if (f.size() == dotted.size() || f[dotted.size()] == '[' || f[dotted.size()] == '.')
      return true;
  }
  return false;
}

std::string formatNumber(double v) {
  char buf[40];
  for (int prec = 6; prec <= 17; ++prec) {
    std::snprintf(buf, sizeof(buf), "%.*g", prec, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

void ParamReader::failGeneral(const std::string& what) { problems_.push_back(what); }

void ParamReader::rejectUnusedUnder(const std::string& dotted) {
  for (const auto& k : unusedUnder(dotted))
    fail(k, "unknown key (not a parameter of this package)");
}

void ParamReader::throwIfProblems() const {
  if (!problems_.empty()) throw ConfigError(problems_);
}

}  // namespace preadaptive_mrac
