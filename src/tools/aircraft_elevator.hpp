#pragma once
/// \file aircraft_elevator.hpp
/// \brief The elevator a batch run beyond the paper flies when the user names none: an
/// ordinary JSBSim aircraft's own, else the B-747's preset. Shared by preadapt_sim and
/// preadapt_family (the tools that link the plant engines).

#include <string>

#include "cli_common.hpp"

namespace preadaptive_mrac {
namespace cli {

/// \brief Adds to `req` the elevator of its aircraft (`plant`: the plant of a run prepared from
/// `req`) and returns what the reports call it:
/// - plant.engine jsbsim with an ordinary aircraft (no package interface): the travel and rate
///   of its flight control system as plant.actuator overrides, before the user's --set
///   ("aircraft"); when its flight control system gives none, the plant file's own ("plant
///   file", said on stderr by `tool`);
/// - otherwise config/plant/elevator_b747.yaml over the plant file ("b747"), unless
///   `b747_for_linear` is false and the engine is linear (nothing added: "plant file").
/// Throws JsbsimError (an aircraft that does not load).
std::string addAircraftElevator(const PlantConfig& plant, RunRequest* req, const std::string& tool,
                                bool b747_for_linear);

}  // namespace cli
}  // namespace preadaptive_mrac
