#pragma once
/// \file plant_conditions.hpp
/// \brief One record of the plant's conditions: what the plant simulator
/// did over a step beyond the paper's ideal plant, produced once by ScenarioPlant and read by
/// every consumer from its table: the closed loop's Series, the CSV columns (io/setup.cpp),
/// the ROS truth message's `conditions` array (plant node), and through their names the
/// Python readers and figures (analysis/csv_runs.py, bags.py, figures.py).
///
/// A new condition (docs/design.md, "A new plant condition") is its part under core/sim/, one
/// field here, one row of kPlantConditionTable, and the line in ScenarioPlant that sets it.
///
/// Rows marked `engine` are what a six-degree-of-freedom engine (plant.engine jsbsim) knows
/// and the linear model never had (pitch attitude, airspeed, altitude, flight path angle):
/// a record has them only when the plant is such an engine (ConditionRows), so a run of the
/// linear plant writes, publishes and reads exactly what it did before they existed.

#include <array>

namespace preadaptive_mrac {

/// \brief The plant's conditions at sample k, one number each (a flag is 0 or 1).
struct PlantConditions {
  double u_applied = 0.0;      ///< elevator applied over the step [rad] (after delay, lag, limits)
  double effectiveness = 1.0;  ///< elevator effectiveness Lambda held over the step
  double w_gust = 0.0;         ///< Dryden vertical gust w_g held over the step [m/s]
  double plant_limited = 0.0;  ///< 1 when the actuator's limits changed the step's signal
  // An engine's flight outputs at t_k (plant_engine.hpp FlightOutputs; 0 on the linear plant)
  double pitch = 0.0;        ///< pitch attitude theta [rad]
  double airspeed = 0.0;     ///< true airspeed [m/s]
  double altitude = 0.0;     ///< altitude above sea level [m]
  double flight_path = 0.0;  ///< flight path angle gamma [rad]
};

/// \brief When a condition is known: at t_k, before the step (a value held over it, or of the
/// state at t_k), or only after the step (what the step did).
enum class ConditionKnown { kBeforeStep, kAfterStep };

/// \brief One row of the table: the field, its name (the CSV column, the name in
/// PlantTruth.condition_names and in Python's Run.conditions), unit, when it is known, and
/// whether only an engine has it.
struct PlantConditionColumn {
  const char* name;
  double PlantConditions::*field;
  const char* unit;  ///< "" for a number without unit, "flag" for 0/1 (written as an integer)
  ConditionKnown known;
  bool engine = false;  ///< a flight output of plant.engine jsbsim (ConditionRows::engine)
  bool isFlag() const { return unit[0] == 'f'; }
};

/// \brief The conditions in the order of the CSV's columns and the truth message's array (the
/// engine's rows last, so a record without them is the table's first rows).
inline constexpr std::array<PlantConditionColumn, 8> kPlantConditionTable{{
    {"u_applied", &PlantConditions::u_applied, "rad", ConditionKnown::kAfterStep},
    {"effectiveness", &PlantConditions::effectiveness, "", ConditionKnown::kBeforeStep},
    {"w_gust", &PlantConditions::w_gust, "m/s", ConditionKnown::kBeforeStep},
    {"plant_limited", &PlantConditions::plant_limited, "flag", ConditionKnown::kAfterStep},
    {"pitch", &PlantConditions::pitch, "rad", ConditionKnown::kBeforeStep, true},
    {"airspeed", &PlantConditions::airspeed, "m/s", ConditionKnown::kBeforeStep, true},
    {"altitude", &PlantConditions::altitude, "m", ConditionKnown::kBeforeStep, true},
    {"flight_path", &PlantConditions::flight_path, "rad", ConditionKnown::kBeforeStep, true},
}};

/// \brief Which rows of the table a run's record has: the plant's (`plant`: the rows of the
/// actuator chain, Lambda and the gust) and the engine's (`engine`: plant.engine is not
/// linear). The CSV writes the plant's rows only for a plant with conditions
/// (ScenarioPlant::hasConditions), the truth message and the envelope exit always.
struct ConditionRows {
  bool plant = false;
  bool engine = false;
  bool has(const PlantConditionColumn& c) const { return c.engine ? engine : plant; }
  bool any() const { return plant || engine; }
};

/// \brief The record of step k as the batch loop keeps it: `before` taken at t_k (before the
/// step), with the fields known only after the step taken from `after`.
inline PlantConditions completeStep(const PlantConditions& before, const PlantConditions& after) {
  PlantConditions c = before;
  for (const PlantConditionColumn& col : kPlantConditionTable)
    if (col.known == ConditionKnown::kAfterStep) c.*col.field = after.*col.field;
  return c;
}

}  // namespace preadaptive_mrac
