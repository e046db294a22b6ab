#include "preadaptive_mrac/core/event.hpp"

namespace preadaptive_mrac {

const char* eventTypeName(Event::Type t) {
  switch (t) {
    case Event::Type::kOnset:
      return "onset";
    case Event::Type::kRecovered:
      return "recovered";
    case Event::Type::kIgnoredOnset:
      return "ignored_onset";
    case Event::Type::kIgnoredRecovery:
      return "ignored_recovery";
    case Event::Type::kDecision:
      return "decision";
  }
  return "?";
}

const char* decisionName(Event::Decision d) {
  switch (d) {
    case Event::Decision::kNone:
      return "none";
    case Event::Decision::kKeep:
      return "keep";
    case Event::Decision::kFit:
      return "fit";
    case Event::Decision::kMemory:
      return "memory";
    case Event::Decision::kNetwork:
      return "network";
  }
  return "?";
}

}  // namespace preadaptive_mrac
