#include "preadaptive_mrac/core/schema/param_table.hpp"

#include <cstdint>
#include <limits>

namespace preadaptive_mrac {

void readScalar(ParamReader& r, const std::string& key, const ParamSpec& s, double* v) {
  *v = s.presence == ParamPresence::kOptional ? r.getDouble(key, *v) : r.getDouble(key);
}

void readScalar(ParamReader& r, const std::string& key, const ParamSpec& s, int* v) {
  const std::int64_t w = s.presence == ParamPresence::kOptional ? r.getInt(key, *v) : r.getInt(key);
  // Checked before the cast: a value beyond int would wrap and could land inside the range.
  if (w < std::numeric_limits<int>::min() || w > std::numeric_limits<int>::max()) {
    r.fail(key, "must fit a 32-bit int, got " + std::to_string(w));
    return;
  }
  *v = static_cast<int>(w);
}

void readScalar(ParamReader& r, const std::string& key, const ParamSpec& s, std::uint64_t* v) {
  const std::int64_t w = s.presence == ParamPresence::kOptional
                             ? r.getInt(key, static_cast<std::int64_t>(*v))
                             : r.getInt(key);
  // Checked here, not by the row's check: the unsigned member cannot hold what was refused.
  if (w < 0) {
    if (r.usable(key)) r.fail(key, "must be >= 0, got " + std::to_string(w));
    return;
  }
  *v = static_cast<std::uint64_t>(w);
}

void readScalar(ParamReader& r, const std::string& key, const ParamSpec& s, bool* v) {
  *v = s.presence == ParamPresence::kOptional ? r.getBool(key, *v) : r.getBool(key);
}

void readScalar(ParamReader& r, const std::string& key, const ParamSpec& s, std::string* v) {
  *v = s.presence == ParamPresence::kOptional ? r.getString(key, *v) : r.getString(key);
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
