#pragma once
/// \file plant_conditions.hpp
/// \brief One record of the plant's conditions (issue 34 item 3): what the plant simulator
/// did over a step beyond the paper's ideal plant, produced once by ScenarioPlant and read by
/// every consumer from its table: the closed loop's Series, the CSV columns (io/setup.cpp),
/// the ROS truth message's `conditions` array (plant node), and through their names the
/// Python readers and figures (analysis/csv_runs.py, bags.py, figures.py).
///
/// A new condition (docs/design.md, "A new plant condition") is its part under core/sim/, one
/// field here, one row of kPlantConditionTable, and the line in ScenarioPlant that sets it.

#include <array>

namespace preadaptive_mrac {

/// \brief The plant's conditions at sample k, one number each (a flag is 0 or 1).
struct PlantConditions {
  double u_applied = 0.0;      ///< elevator applied over the step [rad] (after delay, lag, limits)
  double effectiveness = 1.0;  ///< elevator effectiveness Lambda held over the step
  double w_gust = 0.0;         ///< Dryden vertical gust w_g held over the step [m/s]
  double plant_limited = 0.0;  ///< 1 when the actuator's limits changed the step's signal
};

/// \brief When a condition is known: at t_k, before the step (a value held over it, or of the
/// state at t_k), or only after the step (what the step did).
enum class ConditionKnown { kBeforeStep, kAfterStep };

/// \brief One row of the table: the field, its name (the CSV column, the name in
/// PlantTruth.condition_names and in Python's Run.conditions), unit, and when it is known.
struct PlantConditionColumn {
  const char* name;
  double PlantConditions::*field;
  const char* unit;  ///< "" for a number without unit, "flag" for 0/1 (written as an integer)
  ConditionKnown known;
  bool isFlag() const { return unit[0] == 'f'; }
};

/// \brief The conditions in the order of the CSV's columns and the truth message's array.
inline constexpr std::array<PlantConditionColumn, 4> kPlantConditionTable{{
    {"u_applied", &PlantConditions::u_applied, "rad", ConditionKnown::kAfterStep},
    {"effectiveness", &PlantConditions::effectiveness, "", ConditionKnown::kBeforeStep},
    {"w_gust", &PlantConditions::w_gust, "m/s", ConditionKnown::kBeforeStep},
    {"plant_limited", &PlantConditions::plant_limited, "flag", ConditionKnown::kAfterStep},
}};

/// \brief The record of step k as the batch loop keeps it: `before` taken at t_k (before the
/// step), with the fields known only after the step taken from `after`.
inline PlantConditions completeStep(const PlantConditions& before, const PlantConditions& after) {
  PlantConditions c = before;
  for (const PlantConditionColumn& col : kPlantConditionTable)
    if (col.known == ConditionKnown::kAfterStep) c.*col.field = after.*col.field;
  return c;
}

}  // namespace preadaptive_mrac
