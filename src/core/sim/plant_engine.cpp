#include "preadaptive_mrac/core/sim/plant_engine.hpp"

#include <map>
#include <string>
#include <utility>

#include "preadaptive_mrac/core/sim/plant.hpp"

namespace preadaptive_mrac {

namespace {

// Function-local: engines register from static initialisers of other libraries, whose order
// against this file's is unspecified.
std::map<PlantEngineKind, PlantEngineFactory>& registry() {
  static std::map<PlantEngineKind, PlantEngineFactory> engines;
  return engines;
}

}  // namespace

const char* const kFaultsNeedAerodynamics =
    "physical faults (CG shift, elevator effectiveness, pitch damping) need plant.engine jsbsim";

bool registerPlantEngine(PlantEngineKind kind, PlantEngineFactory factory) {
  registry()[kind] = std::move(factory);
  return true;
}

bool hasPlantEngine(PlantEngineKind kind) {
  return kind == PlantEngineKind::kLinear || registry().count(kind) > 0;
}

std::unique_ptr<PlantEngine> makePlantEngine(const PlantConfig& cfg, double dt) {
  if (cfg.engine == PlantEngineKind::kLinear) return nullptr;
  const auto it = registry().find(cfg.engine);
  if (it == registry().end())
    throw PlantEngineError(std::string("plant.engine ") + choiceName(cfg.engine) +
                           ": this program was built without that engine (link its library, "
                           "e.g. preadaptive_mrac_jsbsim)");
  return it->second(cfg, dt);
}

PlantEngineRules plantEngineRules(PlantEngineKind kind) {
  PlantEngineRules rules;
  if (kind == PlantEngineKind::kJsbsim) {
    rules.flight_outputs = true;
    rules.physical_faults = true;
  }
  return rules;
}

}  // namespace preadaptive_mrac
