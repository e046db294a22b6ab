#include "preadaptive_mrac/core/control/event.hpp"

#include <cstddef>

namespace preadaptive_mrac {

namespace {
template <size_t N, class E>
const char* nameOf(const char* const (&names)[N], E value) {
  const auto i = static_cast<size_t>(value);
  return i < N ? names[i] : "?";
}
}  // namespace

// In the order of the enumerators (event.hpp).
const char* eventTypeName(Event::Type t) {
  static const char* const kNames[] = {"onset", "recovered", "ignored_onset", "ignored_recovery",
                                       "decision"};
  return nameOf(kNames, t);
}

const char* decisionName(Event::Decision d) {
  static const char* const kNames[] = {"none", "keep", "fit", "memory", "network"};
  return nameOf(kNames, d);
}

}  // namespace preadaptive_mrac
