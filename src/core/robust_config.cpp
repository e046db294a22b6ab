#include "preadaptive_mrac/core/robust_config.hpp"

#include "preadaptive_mrac/core/params.hpp"

namespace preadaptive_mrac {

namespace {
// The real-valued keys of controller.robust with their ranges: one table for reading and
// validating (and in the order a start-up line names the defaults).
struct RobustKey {
  const char* key;
  double RobustConfig::*member;
  double lo, hi;
  bool lo_open;
};
constexpr RobustKey kRobustKeys[] = {
    {"detect_window", &RobustConfig::detect_window, 0.0, 10.0, true},
    {"long_window", &RobustConfig::long_window, 0.0, 10.0, false},
    {"chunk", &RobustConfig::chunk, 0.0, 10.0, true},
    {"threshold", &RobustConfig::threshold, 0.0, 100.0, true},
    {"noise_factor", &RobustConfig::noise_factor, 0.0, 1000.0, false},
    {"noise_time", &RobustConfig::noise_time, 0.0, 1e6, true},
    {"verify_time", &RobustConfig::verify_time, 0.0, 10.0, true},
    {"margin", &RobustConfig::margin, 0.0, 1.0, false},
    {"significance", &RobustConfig::significance, 0.0, 1e6, false},
    {"prior_std", &RobustConfig::prior_std, 0.0, 1e6, true},
    {"ridge", &RobustConfig::ridge, 0.0, 1e6, false},
    {"cl_gain", &RobustConfig::cl_gain, 0.0, 1e6, false},
    {"merge_tolerance", &RobustConfig::merge_tolerance, 0.0, 100.0, false},
    {"settle_time", &RobustConfig::settle_time, 0.0, 1e6, false},
    {"quiet_time", &RobustConfig::quiet_time, 0.0, 1e6, true},
    {"network_rate", &RobustConfig::network_rate, 0.0, 1e3, false},
};
}  // namespace

RobustConfig RobustConfig::read(ParamReader& r, const std::string& p) {
  RobustConfig c;
  if (!r.has(p)) {  // optional section: the documented defaults
    r.noteDefault(p, "absent (pa_robust's documented defaults)");
    return c;
  }
  // Each key is optional: an absent one keeps its documented default (noted, so the tools
  // and nodes print it), so `--set controller.robust.margin=0.3` works on any file.
  for (const RobustKey& k : kRobustKeys)
    c.*(k.member) = r.getDouble(p + "." + k.key, c.*(k.member));
  c.memory_size = static_cast<int>(r.getInt(p + ".memory_size", c.memory_size));
  c.use_network = r.getBool(p + ".use_network", c.use_network);
  return c;
}

void RobustConfig::validate(ParamReader& r, const std::string& p) const {
  auto range = [&](const std::string& key, double v, double lo, double hi, bool lo_open) {
    const std::string k = p + "." + key;
    if (!r.usable(k)) return;
    const bool ok = (lo_open ? v > lo : v >= lo) && v <= hi;
    if (!ok)
      r.fail(k, std::string("must be in ") + (lo_open ? "(" : "[") + formatNumber(lo) + ", " +
                    formatNumber(hi) + "], got " + formatNumber(v));
  };
  for (const RobustKey& k : kRobustKeys) range(k.key, this->*(k.member), k.lo, k.hi, k.lo_open);
  range("memory_size", memory_size, 0.0, 1024.0, false);
  // The pairs are checked when either key is given (the other may be its default).
  auto pair = [&](const std::string& a, const std::string& b) {
    return (r.has(p + a) || r.has(p + b)) && !r.failed(p + a) && !r.failed(p + b);
  };
  if (pair(".verify_time", ".detect_window") && verify_time < detect_window)
    r.fail(p + ".verify_time", "must be >= detect_window (" + formatNumber(detect_window) +
                                   "), got " + formatNumber(verify_time));
  if (pair(".long_window", ".detect_window") && long_window > 0.0 && long_window < detect_window)
    r.fail(p + ".long_window", "must be 0 (off) or >= detect_window (" +
                                   formatNumber(detect_window) + "), got " +
                                   formatNumber(long_window));
  if (pair(".chunk", ".verify_time") && chunk > verify_time)
    r.fail(p + ".chunk", "must be <= verify_time (" + formatNumber(verify_time) + "), got " +
                             formatNumber(chunk));
}

}  // namespace preadaptive_mrac
