#include "preadaptive_mrac/core/tunables.hpp"

#include <cmath>

namespace preadaptive_mrac {

namespace {

// (key, value, kind): kind 'd' double, 'i' int, 'b' bool; the tree validateTunables builds.
struct Typed {
  const char* key;
  double value;
  char kind;
};

std::vector<Typed> typedEntries(const ControllerTunables& t) {
  const RobustConfig& r = t.robust;
  return {
      {"attention.c_e", t.c_e, 'd'},
      {"attention.c_ed", t.c_ed, 'd'},
      {"attention.confirm_samples", static_cast<double>(t.confirm_samples), 'i'},
      {"attention.hysteresis", t.hysteresis, 'd'},
      {"adaptation.gamma", t.gamma, 'd'},
      {"preadaptation.gamma_pa", t.gamma_pa, 'd'},
      {"projection.enabled", t.projection ? 1.0 : 0.0, 'b'},
      {"projection.theta_max", t.theta_max, 'd'},
      {"projection.epsilon", t.projection_epsilon, 'd'},
      {"robust.detect_window", r.detect_window, 'd'},
      {"robust.long_window", r.long_window, 'd'},
      {"robust.chunk", r.chunk, 'd'},
      {"robust.threshold", r.threshold, 'd'},
      {"robust.noise_factor", r.noise_factor, 'd'},
      {"robust.noise_time", r.noise_time, 'd'},
      {"robust.verify_time", r.verify_time, 'd'},
      {"robust.margin", r.margin, 'd'},
      {"robust.significance", r.significance, 'd'},
      {"robust.prior_std", r.prior_std, 'd'},
      {"robust.ridge", r.ridge, 'd'},
      {"robust.cl_gain", r.cl_gain, 'd'},
      {"robust.memory_size", static_cast<double>(r.memory_size), 'i'},
      {"robust.merge_tolerance", r.merge_tolerance, 'd'},
      {"robust.settle_time", r.settle_time, 'd'},
      {"robust.quiet_time", r.quiet_time, 'd'},
      {"robust.use_network", r.use_network ? 1.0 : 0.0, 'b'},
      {"robust.network_rate", r.network_rate, 'd'},
  };
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
