#include "aircraft_elevator.hpp"

#include <cstdio>
#include <iostream>
#include <optional>
#include <vector>

#include "preadaptive_mrac/jsbsim/jsbsim_overlay.hpp"

namespace preadaptive_mrac {
namespace cli {

namespace {

/// The travel and rate of an ordinary JSBSim aircraft's elevator as plant.actuator overrides
/// (none when its flight control system does not give both).
std::vector<std::string> aircraftElevatorSets(const JsbsimElevator& el) {
  if (!el.limitsKnown()) return {};
  char travel[64], rate[64];
  std::snprintf(travel, sizeof travel, "plant.actuator.max_deflection=%.17g", el.symmetricTravel());
  std::snprintf(rate, sizeof rate, "plant.actuator.max_rate=%.17g", el.max_rate);
  return {"plant.actuator.enabled=true", travel, rate};
}

}  // namespace

std::string addAircraftElevator(const PlantConfig& plant, RunRequest* req, const std::string& tool,
                                bool b747_for_linear) {
  if (plant.engine == PlantEngineKind::kJsbsim) {
    if (const std::optional<JsbsimElevator> el = jsbsimOrdinaryElevator(plant.jsbsim)) {
      const std::vector<std::string> own = aircraftElevatorSets(*el);
      if (own.empty()) {
        std::cerr << tool << ": the aircraft '" << plant.jsbsim.aircraft
                  << "' gives no elevator travel and rate in its flight control system: its "
                     "elevator is the plant file's own (give one with --elevator FILE)"
                  << std::endl;
        return "plant file";
      }
      req->sets.insert(req->sets.begin(), own.begin(), own.end());
      return "aircraft";
    }
  } else if (!b747_for_linear) {
    return "plant file";
  }
  req->plant_presets.push_back(elevatorPresetPath("--elevator", "b747"));
  return "b747";
}

}  // namespace cli
}  // namespace preadaptive_mrac
