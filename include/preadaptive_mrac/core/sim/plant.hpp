#pragma once
/// \file plant.hpp
/// \brief The plant x_dot = A x + B (theta^T x + u) + B1r r (eq. plant), integrated with RK4.

#include <cstdint>
#include <random>
#include <string>

#include "preadaptive_mrac/core/elevator_limits.hpp"
#include "preadaptive_mrac/core/sim/envelope.hpp"
#include "preadaptive_mrac/core/types.hpp"
#include "preadaptive_mrac/params/plant_params.hpp"

namespace preadaptive_mrac {

class ParamReader;

// The scalars of each part (enabled, max_deflection, ...: members, defaults, ranges) are the
// structs generated from params/plant.yaml; the parts add the vectors and the behaviour.

/// \brief Elevator magnitude and rate limits (key plant.actuator; optional, off when absent):
/// enabled, max_deflection [rad] (|u| <= it), max_rate [rad/s] (|du/dt| <= it).
struct ActuatorLimits : ActuatorLimitsParams {
  /// \brief The deflection the actuator reaches over one step of dt [s] when commanded u
  /// from u_prev [rad]: ElevatorLimits::apply, the rule the controller applies too.
  double apply(double u, double u_prev, double dt) const;
  /// \brief The same limits as the controller knows them (DesignModel::limits).
  ElevatorLimits elevator() const { return ElevatorLimits{enabled, max_deflection, max_rate}; }
};

/// \brief Largest plant.actuator.delay accepted [s] (the delay line's memory is delay / dt).
constexpr double kMaxDelay = 3600.0;

/// \brief Delay and lag of the elevator servo (keys plant.actuator.delay and
/// plant.actuator.time_constant; 0 when absent, the paper's instant elevator): delay [s],
/// rounded to whole samples, and the first-order lag T [s] (0 = none). The table's range of
/// the delay ends at kMaxDelay (test_plant_parts holds them equal).
struct ActuatorDynamics : ActuatorDynamicsParams {};

/// \brief Key plant.turbulence (optional; off when absent): enabled, sigma_w (standard
/// deviation of the vertical gust w_g [m/s]), length_scale (Dryden L_w [m]), seed (the gust's
/// own noise stream).
struct TurbulenceConfig : TurbulenceParams {
  bool active() const { return enabled && sigma_w > 0.0; }
};

/// \brief Gaussian noise added to the measured state (key plant.noise; optional, off when
/// absent); its seed is the generated part.
struct MeasurementNoise : MeasurementNoiseParams {
  Eigen::VectorXd std;  ///< standard deviation per state (n) [units of x]
  bool active() const { return std.size() > 0 && std.cwiseAbs().maxCoeff() > 0.0; }
};

/// \brief Seeded standard normal numbers, the same on every platform (mt19937_64 + Box-Muller;
/// std::normal_distribution is implementation-defined).
class GaussianSource {
 public:
  explicit GaussianSource(std::uint64_t seed = 0) : gen_(seed) {}
  double next();
  void reseed(std::uint64_t seed) {
    gen_.seed(seed);
    has_spare_ = false;
  }

 private:
  std::mt19937_64 gen_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

/// \brief Plant model and initial state, as read from config/plant/*.yaml (key `plant`); the
/// generated part holds output_index (y = x[output_index], alpha) and airspeed
/// (plant.operating_point.U [m/s]; 0 when absent, needed by turbulence).
struct PlantConfig : PlantParams {
  Eigen::MatrixXd A;            ///< state matrix (n x n)
  Eigen::VectorXd B;            ///< input vector (n)
  Eigen::VectorXd B1r;          ///< reference input vector (n)
  Eigen::VectorXd x0;           ///< initial state (n) [e_I rad s, alpha rad, q rad/s]
  ActuatorLimits actuator;      ///< applied by the plant, known to the controller
  MeasurementNoise noise;       ///< added to what the plant publishes as measured
  ActuatorDynamics dynamics;    ///< servo delay and lag (the controller is not told)
  TurbulenceConfig turbulence;  ///< Dryden vertical gust (the controller is not told)
  FlightEnvelope envelope;      ///< bounds the plant checks on every step
  JsbsimParams jsbsim;          ///< the JSBSim process and operating point (engine jsbsim)

  int n() const { return static_cast<int>(A.rows()); }
  /// \brief Read the `plant` section; problems go to the reader.
  static PlantConfig read(ParamReader& r, const std::string& prefix = "plant");
  /// \brief Add every problem of the values themselves (sizes, finiteness) to the reader.
  void validate(ParamReader& r, const std::string& prefix = "plant") const;
  /// \brief The rules of plant.engine jsbsim: x = [e_I, alpha, q] with e_I_dot = alpha - r,
  /// starting at the trim.
  void validateJsbsim(ParamReader& r, const std::string& prefix) const;
};

/// \brief The simulation truth: integrates the plant one step with theta, u and r held.
class Plant {
 public:
  explicit Plant(const PlantConfig& cfg);

  /// \brief Advance x by dt [s] with classic RK4; theta, u [rad] and r [rad] constant over the
  /// step. For n = 3 (the B-747 plant) an unrolled path with the same operations in the same
  /// order, so the same bits (test_fast_paths, FastPaths.PlantStepHasTheBitsOfTheGenericStep,
  /// checks it against the generic path).
  void step(double dt, const Vec& theta, double u, double r);
  /// \brief step() with a disturbance d (n) [units of x_dot] added to x_dot, held over the step
  /// (the generic path for any n: a disturbed run has no bits of the paper's to keep).
  void stepDisturbed(double dt, const Vec& theta, double u, double r, const Vec& d);
  /// \brief Time derivative at (x, theta, u, r).
  void derivative(const Vec& x, const Vec& theta, double u, double r, Vec* xdot) const;

  const Vec& state() const { return x_; }
  void setState(const Vec& x) { x_ = x; }
  void reset() { x_ = x0_; }
  int n() const { return static_cast<int>(A_.rows()); }
  int outputIndex() const { return out_; }
  const Mat& A() const { return A_; }
  const Vec& B() const { return B_; }
  const Vec& B1r() const { return B1r_; }

 private:
  Mat A_;
  Vec B_, B1r_, x0_, x_;
  int out_;
  Vec k1_, k2_, k3_, k4_, tmp_;
  /// \brief The RK4 step of the generic path (any n), with Eigen's run-time sized types.
  void stepGeneric(double dt, const Vec& theta, double u, double r);
  /// \brief The RK4 step for n = 3 on scalars: no size checks or loops at run time.
  void step3(double dt, const Vec& theta, double u, double r);
  bool three_ = false;  // n == 3: step() takes step3()
  double a3_[9] = {};   // A, row-major (n = 3)
  double b3_[3] = {}, b1r3_[3] = {};
};

}  // namespace preadaptive_mrac
