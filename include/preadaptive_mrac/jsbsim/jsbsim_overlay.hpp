#pragma once
/// \file jsbsim_overlay.hpp
/// \brief Any JSBSim aircraft as the package's plant (STL only): when an aircraft lacks the
/// package's interface (the pmrac-interface system of jsbsim/aircraft/b747_pmrac), an overlay
/// root is generated in a temporary folder: the user's aircraft folder linked file by file, its
/// aircraft file rewritten to add the interface (a <system> of its own for the inputs, the
/// full-precision outputs and the step marker in the aerodynamics, which runs after the
/// integrator), and the elevator driven through the aircraft's own flight control system
/// (plant.jsbsim.elevator `command`: fcs/elevator-cmd-norm) or at the surface (`surface`:
/// fcs/elevator-pos-rad is the aircraft's own trimmed deflection plus the package's). The
/// user's files are never written.

#include <optional>
#include <string>

#include "preadaptive_mrac/params/plant_params.hpp"

namespace preadaptive_mrac {

/// \brief The elevator the package found in an aircraft's flight control system.
struct JsbsimElevator {
  std::string writer;            ///< the component writing fcs/elevator-pos-rad: "<type> 'name'"
  double rad_per_command = 0.0;  ///< d fcs/elevator-pos-rad / d fcs/elevator-cmd-norm [rad]
  double min_rad = 0.0;          ///< the surface's travel: lowest deflection [rad]
  double max_rad = 0.0;          ///< highest deflection [rad] (min = max = 0: none found)
  double max_rate = 0.0;         ///< the actuator's rate limit [rad/s] (0: none found)
  /// \brief True when the FCS gives the surface a travel (a clip or a scale's range).
  bool travelKnown() const { return max_rad > min_rad; }
  /// \brief True when the FCS gives both a travel and a rate limit: what the package needs to
  /// fly the aircraft's own elevator (plant.actuator).
  bool limitsKnown() const { return travelKnown() && max_rate > 0.0; }
  /// \brief The package's symmetric travel about the trim: the smaller of the two stops [rad].
  double symmetricTravel() const;
};

/// \brief True when the aircraft file's text carries the package's interface (it names
/// fcs/pmrac-elevator-cmd-rad): such an aircraft is flown as it is.
bool jsbsimHasInterface(const std::string& aircraft_xml);

/// \brief The elevator of the aircraft `aircraft` under `root` (its <flight_control>,
/// <autopilot> and <system> elements, inline or in the files they name). Throws JsbsimError
/// naming the key and the cause when there is none the package can drive with `drive`.
JsbsimElevator findJsbsimElevator(const std::string& root, const std::string& aircraft,
                                  JsbsimElevatorDrive drive);

/// \brief The elevator of the aircraft of `params` (its root found as findJsbsimRoot does) when
/// it lacks the package's interface, else nothing (b747_pmrac: the package knows its elevator
/// from config/plant/elevator_b747.yaml). Throws JsbsimError as findJsbsimExecutable,
/// findJsbsimRoot and findJsbsimElevator do.
std::optional<JsbsimElevator> jsbsimOrdinaryElevator(const JsbsimParams& params);

/// \brief The root JSBSim is started on: the user's own (an aircraft with the interface), or a
/// generated overlay removed with this object.
class JsbsimOverlay {
 public:
  /// \brief `root`: the resolved plant.jsbsim.root (findJsbsimRoot). Throws JsbsimError.
  JsbsimOverlay(const std::string& root, const JsbsimParams& params);
  ~JsbsimOverlay();
  JsbsimOverlay(const JsbsimOverlay&) = delete;
  JsbsimOverlay& operator=(const JsbsimOverlay&) = delete;

  /// \brief JSBSim's --root: the overlay's, or the user's when nothing was generated.
  const std::string& root() const { return root_; }
  /// \brief The initial condition to load: plant.jsbsim.initialize, or, for an overlay whose
  /// aircraft folder has no such file while the key is at its default, a generated level start
  /// at the operating point (pmrac_operating_point).
  const std::string& initialize() const { return initialize_; }
  /// \brief True when an overlay was generated (the aircraft lacks the interface).
  bool generated() const { return !dir_.empty(); }
  /// \brief The elevator found (generated() only).
  const JsbsimElevator& elevator() const { return elevator_; }

 private:
  std::string root_, initialize_, dir_;
  JsbsimElevator elevator_;
};

}  // namespace preadaptive_mrac
