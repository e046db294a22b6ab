#pragma once
/// \file part_registry.hpp
/// \brief The adaptive laws and preadaptation strategies a program holds, by name: what a part
/// registers itself in, one line in its own .cpp, and what the modes (controller/
/// mode_registry.hpp, params/modes.yaml's `law` and `strategy`) are made of. Below every part,
/// so a part in its folder registers without including the controller above it.

#include <memory>
#include <string>
#include <vector>

namespace preadaptive_mrac {

class AdaptiveLaw;
class PreadaptationStrategy;
struct ModeContext;

/// \brief Makes a law for a controller (a captureless lambda converts to it).
using LawFactory = std::unique_ptr<AdaptiveLaw> (*)(const ModeContext&);
/// \brief Makes a preadaptation strategy for a controller.
using StrategyFactory = std::unique_ptr<PreadaptationStrategy> (*)(const ModeContext&);

/// \brief A registered adaptive law: the name params/modes.yaml's `law` gives it.
struct LawEntry {
  const char* name;
  LawFactory make;
};

/// \brief A registered preadaptation strategy: the name params/modes.yaml's `strategy` gives it.
struct StrategyEntry {
  const char* name;
  StrategyFactory make;
};

/// \brief Register the law `make` under `name`: one line in the law's own .cpp, run by a static
/// initialiser, `const bool kRegistered = registerLaw("deadzone", makeDeadzoneLaw);`.
/// Returns true; throws std::logic_error naming `name` when it is empty, `make` is null or a
/// law of that name is registered already (the built-in ones included: mode_registry.hpp).
/// Register before any thread reads the registry (a static initialiser or the top of main):
/// it takes no lock.
bool registerLaw(const std::string& name, LawFactory make);
/// \brief The same for a preadaptation strategy.
bool registerStrategy(const std::string& name, StrategyFactory make);

/// \brief Every registered adaptive law, in the order registered.
const std::vector<LawEntry>& lawRegistry();
/// \brief Every registered preadaptation strategy, in the order registered.
const std::vector<StrategyEntry>& strategyRegistry();
/// \brief The law registered as `name`, or null.
LawFactory findLaw(const std::string& name);
/// \brief The strategy registered as `name`, or null.
StrategyFactory findStrategy(const std::string& name);

}  // namespace preadaptive_mrac
