#include "preadaptive_mrac/core/control/part_registry.hpp"

#include <deque>
#include <stdexcept>

namespace preadaptive_mrac {

namespace {

// Function-local: parts register from static initialisers, whose order across files is not
// fixed, so the tables are built by the first registration or read, whichever comes first.
std::vector<LawEntry>& laws() {
  static std::vector<LawEntry> all;
  return all;
}

std::vector<StrategyEntry>& strategies() {
  static std::vector<StrategyEntry> all;
  return all;
}

// The names, kept where the entries' `const char*` point at (a deque never moves them).
const char* keepName(const std::string& name) {
  static std::deque<std::string> kept;
  kept.push_back(name);
  return kept.back().c_str();
}

template <class Entry>
auto findIn(const std::vector<Entry>& parts, const std::string& name) -> decltype(parts[0].make) {
  for (const Entry& e : parts)
    if (name == e.name) return e.make;
  return nullptr;
}

// `who`: the registering function, for the message; `kind`: "law" or "strategy".
template <class Entry, class Make>
bool addPart(std::vector<Entry>* parts, const char* who, const char* kind, const std::string& name,
             Make make) {
  if (name.empty() || make == nullptr)
    throw std::logic_error(std::string(who) + ": an empty name or no factory ('" + name + "')");
  if (findIn(*parts, name) != nullptr)
    throw std::logic_error(std::string(who) + ": a " + kind + " named '" + name +
                           "' is registered already");
  parts->push_back({keepName(name), make});
  return true;
}

}  // namespace

bool registerLaw(const std::string& name, LawFactory make) {
  return addPart(&laws(), "registerLaw", "law", name, make);
}

bool registerStrategy(const std::string& name, StrategyFactory make) {
  return addPart(&strategies(), "registerStrategy", "strategy", name, make);
}

const std::vector<LawEntry>& lawRegistry() { return laws(); }

const std::vector<StrategyEntry>& strategyRegistry() { return strategies(); }

LawFactory findLaw(const std::string& name) { return findIn(laws(), name); }

StrategyFactory findStrategy(const std::string& name) { return findIn(strategies(), name); }

}  // namespace preadaptive_mrac
