#include "preadaptive_mrac/core/param_table.hpp"

namespace preadaptive_mrac {

void readScalar(ParamReader& r, const std::string& key, const ParamSpec& s, double* v) {
  *v = s.presence == ParamPresence::kOptional ? r.getDouble(key, *v) : r.getDouble(key);
}

void readScalar(ParamReader& r, const std::string& key, const ParamSpec& s, int* v) {
  *v = static_cast<int>(s.presence == ParamPresence::kOptional ? r.getInt(key, *v) : r.getInt(key));
}

void readScalar(ParamReader& r, const std::string& key, const ParamSpec& s, bool* v) {
  *v = s.presence == ParamPresence::kOptional ? r.getBool(key, *v) : r.getBool(key);
}

void checkScalar(ParamReader& r, const std::string& key, const ParamCheck& c, double v) {
  if (!r.usable(key) || c.holds(v)) return;
  std::string range;
  if (c.has_lo && c.has_hi)
    range = std::string("in ") + (c.lo_open ? "(" : "[") + formatNumber(c.lo) + ", " +
            formatNumber(c.hi) + (c.hi_open ? ")" : "]");
  else if (c.has_lo)
    range = std::string(c.lo_open ? "> " : ">= ") + formatNumber(c.lo);
  else
    range = std::string(c.hi_open ? "< " : "<= ") + formatNumber(c.hi);
  r.fail(key, "must be " + range + ", got " + formatNumber(v));
}

}  // namespace preadaptive_mrac
