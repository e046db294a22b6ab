#pragma once
/// \file jsbsim_plant.hpp
/// \brief JSBSim as the plant engine (plant.engine: jsbsim): the package's aircraft trimmed at
/// an operating point and stepped in socket lockstep, its state read as the package's
/// x = [e_I, alpha, q] (alpha, q from the trim; e_I integrated here).

#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "preadaptive_mrac/core/sim/plant_engine.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_overlay.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_process.hpp"
#include "preadaptive_mrac/params/plant_params.hpp"

namespace preadaptive_mrac {

/// \brief The trimmed operating point (JSBSim's longitudinal trim, level flight).
struct JsbsimTrim {
  double alpha = 0.0;        ///< flight-path angle of attack theta - gamma [rad]
  double pitch = 0.0;        ///< theta [rad]
  double flight_path = 0.0;  ///< gamma [rad]
  double q = 0.0;            ///< pitch rate [rad/s] (not quite 0: the Earth is round)
  double elevator = 0.0;     ///< fcs/elevator-pos-rad [rad] (6 significant digits)
  double throttle = 0.0;     ///< fcs/throttle-cmd-norm (6 significant digits)
  double thrust_lbf = 0.0;   ///< propulsion/engine/thrust-lbs (6 significant digits)
  double airspeed = 0.0;     ///< true airspeed [m/s]
  double altitude = 0.0;     ///< [m]
  double mach = 0.0;         ///< (6 significant digits)
};

/// \brief JSBSim in lockstep: one process per object, trimmed by reset().
///
/// Each step sends one packet `set` elevator (+ vertical wind, faults, a read reference that
/// has fallen behind) and `iterate 1`, then takes from JSBSim's output socket the line of the
/// completed step (pmrac/sync/frame == the frame before + 1) with the deviations
/// pmrac/dev/X = X - pmrac/ref/X (the reference kept within a small bound of X, so the line's
/// 7 significant digits resolve X to ~1e-11 of its unit), and then the packet's replies. The
/// state's alpha is the flight-path angle of attack theta - gamma (what the aircraft's attitude
/// makes with its velocity over the ground), so a vertical wind (the gust, atmosphere/wind-down-fps
/// = -w_g) acts on the aerodynamics without entering x, as on the linear plant. e_I is integrated
/// with the trapezoid rule over the step: e_I += dt ((alpha_k + alpha_k+1) / 2 - r).
class JsbsimPlant : public PlantEngine {
 public:
  /// \brief Start JSBSim and trim it (reset()). `e_i0`: e_I at reset.
  JsbsimPlant(const JsbsimParams& params, double dt, double e_i0);
  void reset() override;
  const Vec& state() const override { return x_; }
  void step(double dt, const Vec& theta, double effect, double r, double gust) override;
  /// \brief Faults act through the aircraft's pmrac/fault/* properties: an aircraft flown
  /// through a generated overlay has none that act, and any fault but the nominal is refused.
  void setFaults(const PhysicalFaults& faults) override;
  const FlightOutputs& flight() const override { return flight_; }
  double trimAirspeed() const override { return trim_.airspeed; }
  void close() override { proc_.stop(); }
  const JsbsimTrim& trim() const { return trim_; }
  JsbsimProcess& process() { return proc_; }
  /// \brief The root JSBSim runs on: the aircraft's own, or an overlay adding the interface.
  const JsbsimOverlay& overlay() const { return overlay_; }
  /// \brief The elevator deflection from the trim [rad] of the last step (effect + theta^T x).
  double lastDeflection() const { return de_; }

 private:
  /// Read the output socket's lines up to the one of `frame` (marker == frame) and take its
  /// values.
  void readFrame(std::int64_t frame);
  /// The state from an output line's deviations and the references.
  void takeOutput(const std::vector<double>& v);
  JsbsimParams params_;
  double dt_;
  double e_i0_;
  JsbsimOverlay overlay_;  // before proc_: JSBSim starts on its root
  JsbsimProcess proc_;
  JsbsimTrim trim_;
  Vec x_;
  FlightOutputs flight_;
  PhysicalFaults faults_, sent_faults_;
  bool wind_sent_ = false;
  std::int64_t frame_ = 0;
  double de_ = 0.0;
  // Full values of the read variables at the current sample (the references of the next read).
  double theta_ = 0.0, gamma_ = 0.0, q_ = 0.0, vt_ = 0.0, h_ = 0.0;
  std::string packet_;
  std::string ic_packet_;  // the initial condition's `set`s, written before every trim
  size_t ic_lines_ = 0;
  /// A read reference: JSBSim's pmrac/ref/X, the value last sent (`at`), and how far X may
  /// move from it before it is sent again.
  struct Ref {
    const char* property;
    const double* value;
    double bound;
    double at = 0.0;
  };
  std::array<Ref, 5> refs_;
};

}  // namespace preadaptive_mrac
