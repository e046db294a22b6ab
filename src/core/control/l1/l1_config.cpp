#include "preadaptive_mrac/core/control/l1/l1_config.hpp"

#include <cmath>

#include "preadaptive_mrac/core/schema/param_table.hpp"

namespace preadaptive_mrac {

L1Config L1Config::read(ParamReader& r, const std::string& p) {
  L1Config c;
  readSection(r, p, &c);
  return c;
}

void L1Config::validate(ParamReader& r, const std::string& p, double sample_time) const {
  checkRanges(r, p, *this);
  // A sampled filter cannot pass more than the Nyquist frequency; past it exp(-omega dt) is
  // so small that C(s) is no filter at all.
  const std::string bw = p + ".bandwidth";
  if (sample_time > 0.0 && !r.failed(bw) && bandwidth > 0.0 && !(bandwidth * sample_time < M_PI))
    r.fail(bw, "must be below pi / sample_time (" + formatNumber(M_PI / sample_time) +
                   " rad/s), got " + formatNumber(bandwidth));
}

}  // namespace preadaptive_mrac
