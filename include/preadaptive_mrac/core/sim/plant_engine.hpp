#pragma once
/// \file plant_engine.hpp
/// \brief What integrates the plant when it is not the linear model (plant.engine): the
/// interface ScenarioPlant steps, and what such an engine reports beyond x.

#include <functional>
#include <memory>
#include <stdexcept>

#include "preadaptive_mrac/core/types.hpp"
#include "preadaptive_mrac/params/plant_params.hpp"

namespace preadaptive_mrac {

struct PlantConfig;

/// \brief What a six-degree-of-freedom engine knows and the linear model never had (SI units),
/// at the current sample.
struct FlightOutputs {
  double pitch = 0.0;        ///< pitch attitude theta [rad]
  double airspeed = 0.0;     ///< true airspeed [m/s]
  double altitude = 0.0;     ///< altitude above sea level [m]
  double flight_path = 0.0;  ///< flight path angle gamma [rad]
};

/// \brief Physical faults of the aircraft (scenario key `faults`), nominal by default.
struct PhysicalFaults {
  double cg_shift = 0.0;                ///< centre-of-gravity shift [fraction of c, + aft]
  double elevator_effectiveness = 1.0;  ///< multiplier of the elevator's aerodynamic derivatives
  double pitch_damping = 1.0;           ///< multiplier of Cmq and Cmalphadot
  bool operator==(const PhysicalFaults& o) const {
    return cg_shift == o.cg_shift && elevator_effectiveness == o.elevator_effectiveness &&
           pitch_damping == o.pitch_damping;
  }
  bool operator!=(const PhysicalFaults& o) const { return !(*this == o); }
};

/// \brief A plant integrator other than the linear model: state x = [e_I, alpha, q] with alpha
/// and q perturbations from the trim, stepped one sample at a time.
class PlantEngine {
 public:
  virtual ~PlantEngine() = default;
  /// \brief Back to the start: the trim, e_I = x0[0], nominal faults.
  virtual void reset() = 0;
  virtual const Vec& state() const = 0;
  /// \brief One step of dt [s] with the elevator's effect `effect` (Lambda times the applied
  /// deflection [rad], from the trim), the matched uncertainty theta^T x added to it, the
  /// command r [rad] and the vertical gust w_g [m/s, + up], all held over the step.
  virtual void step(double dt, const Vec& theta, double effect, double r, double gust) = 0;
  /// \brief Faults from the next step on.
  virtual void setFaults(const PhysicalFaults& faults) = 0;
  virtual const FlightOutputs& flight() const = 0;
  /// \brief The trimmed true airspeed [m/s] (the V of the gust filter).
  virtual double trimAirspeed() const = 0;
  /// \brief Free what the engine holds (JSBSim: end its process) once nothing steps it any
  /// more; state() and flight() keep their last values, step() and reset() then fail.
  virtual void close() = 0;
};

/// \brief What an engine throws when it cannot start or step (JSBSim's JsbsimError is one).
class PlantEngineError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// \brief Starts and trims an engine for a plant configuration and sample time dt [s].
using PlantEngineFactory = std::function<std::unique_ptr<PlantEngine>(const PlantConfig&, double)>;

/// \brief Make `factory` the engine of plant.engine `kind` (one line in the engine's own library,
/// run by a static initialiser: `const bool registered = registerPlantEngine(kind, factory);`).
/// Returns true; a second registration of the same kind replaces the first.
bool registerPlantEngine(PlantEngineKind kind, PlantEngineFactory factory);
/// \brief Whether this program holds an engine for `kind` (always true for `linear`).
bool hasPlantEngine(PlantEngineKind kind);

/// \brief The engine plant.engine names, started and trimmed (nullptr for `linear`: the
/// linear model is ScenarioPlant's own). Throws PlantEngineError when the program was built
/// without that engine, and whatever the engine throws when it cannot run.
std::unique_ptr<PlantEngine> makePlantEngine(const PlantConfig& cfg, double dt);

/// \brief The rules of plant.engine, in one place: what an engine kind has that the linear
/// model has not.
struct PlantEngineRules {
  bool flight_outputs = false;   ///< FlightOutputs and the engine rows of the conditions
  bool physical_faults = false;  ///< scenario.faults (CG, elevator effectiveness, damping)
};
PlantEngineRules plantEngineRules(PlantEngineKind kind);
/// \brief Why scenario faults are refused on an engine without them (the start of the message).
extern const char* const kFaultsNeedAerodynamics;

}  // namespace preadaptive_mrac
