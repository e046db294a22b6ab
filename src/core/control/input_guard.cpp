#include "preadaptive_mrac/core/control/input_guard.hpp"

#include <cmath>
#include <limits>

namespace preadaptive_mrac {

std::string InputGuard::check(const double* x, std::size_t size, const char* field) const {
  if (size != size_)
    return std::string(field) + " has " + std::to_string(size) + " entries, expected " +
           std::to_string(size_);
  if (x == nullptr && size > 0) return std::string(field) + " is missing";
  for (std::size_t i = 0; i < size; ++i) {
    if (std::isnan(x[i])) return std::string(field) + "[" + std::to_string(i) + "] is nan";
    if (std::isinf(x[i])) return std::string(field) + "[" + std::to_string(i) + "] is inf";
  }
  return {};
}

bool InputGuard::accept(double now, const double* x, std::size_t size, std::string* why,
                        const char* field) {
  std::string reason = check(x, size, field);
  if (reason.empty() && !std::isfinite(now)) reason = "time stamp is not finite";
  if (!reason.empty()) {
    ++rejected_;
    last_reason_ = reason;
    if (why) *why = reason;
    return false;
  }
  ++accepted_;
  have_ = true;
  last_valid_ = now;
  return true;
}

double InputGuard::age(double now) const {
  return have_ ? now - last_valid_ : std::numeric_limits<double>::infinity();
}

}  // namespace preadaptive_mrac
