#include "preadaptive_mrac/core/controller/tunables.hpp"

#include <cmath>
#include <type_traits>

namespace preadaptive_mrac {

namespace {

// (key, value, kind): kind 'd' double, 'i' int, 'b' bool; the tree validateTunables builds.
struct Typed {
  const char* key;
  double value;
  char kind;
};

template <class T>
constexpr char kindOf() {
  return std::is_same<T, bool>::value ? 'b' : std::is_same<T, int>::value ? 'i' : 'd';
}

// The tunable rows of the tables (generated forEachTunable), in the tables' order.
std::vector<Typed> typedEntries(const ControllerTunables& t) {
  std::vector<Typed> out;
  forEachTunable(
      [&](const char* key, const char*, const auto& v) {
        out.push_back({key, static_cast<double>(v), kindOf<std::decay_t<decltype(v)>>()});
      },
      t);
  return out;
}

}  // namespace

std::vector<TunableEntry> tunableEntries(const ControllerTunables& t) {
  std::vector<TunableEntry> out;
  for (const Typed& e : typedEntries(t)) out.push_back({e.key, e.value});
  return out;
}

std::vector<TunableChange> diffTunables(const ControllerTunables& from,
                                        const ControllerTunables& to) {
  const std::vector<Typed> a = typedEntries(from), b = typedEntries(to);
  std::vector<TunableChange> out;
  for (size_t i = 0; i < a.size(); ++i) {
    // Bitwise inequality would call -0.0 and 0.0 different; values are validated finite.
    if (a[i].value != b[i].value) out.push_back({a[i].key, a[i].value, b[i].value});
  }
  return out;
}

std::vector<std::string> validateTunables(const ControllerConfig& base, const ControllerTunables& t,
                                          const KeyStyle& style, const std::string& prefix) {
  ControllerConfig c = base;
  t.applyTo(&c);
  const bool check_projection = t.projection || t.theta_max != base.theta_max ||
                                t.projection_epsilon != base.projection_epsilon;
  // A tree holding only the tunable keys: ControllerConfig::validate checks the keys present,
  // so this is the YAML's validation of exactly these values.
  ParamValue tree = ParamValue::makeMap();
  for (const Typed& e : typedEntries(t)) {
    const std::string key(e.key);
    if (!check_projection && key.rfind("projection.", 0) == 0) continue;
    ParamValue v = e.kind == 'b'   ? ParamValue::makeBool(e.value != 0.0)
                   : e.kind == 'i' ? ParamValue::makeInt(static_cast<std::int64_t>(e.value))
                                   : ParamValue::makeDouble(e.value);
    tree.setPath(prefix + "." + key, v);
  }
  if (check_projection) {  // "theta_hat0 lies outside Omega" needs it
    std::vector<ParamValue> th;
    for (int i = 0; i < c.theta_hat0.size(); ++i)
      th.push_back(ParamValue::makeDouble(c.theta_hat0[i]));
    tree.setPath(prefix + ".adaptation.theta_hat0", ParamValue::makeList(th));
  }
  ParamReader r(tree, style);
  for (const Typed& e : typedEntries(t)) {
    if (!std::isfinite(e.value))
      r.fail(prefix + "." + e.key, "must be finite, got " + formatNumber(e.value));
  }
  c.validate(r, static_cast<int>(c.theta_hat0.size()), prefix);
  return r.problems();
}

}  // namespace preadaptive_mrac
