#include "preadaptive_mrac/core/robust/robust_config.hpp"

#include "preadaptive_mrac/core/schema/param_table.hpp"

namespace preadaptive_mrac {

RobustConfig RobustConfig::read(ParamReader& r, const std::string& p) {
  RobustConfig c;
  // Each key is optional: an absent one keeps its declared default (noted, so the tools and
  // nodes print it), so `--set controller.robust.margin=0.3` works on any file.
  readSection(r, p, &c);
  return c;
}

void RobustConfig::validate(ParamReader& r, const std::string& p) const {
  checkRanges(r, p, *this);
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
