#pragma once
/// \file plant.hpp
/// \brief The plant x_dot = A x + B (theta^T x + u) + B1r r (eq. plant), integrated with RK4.

#include <string>

#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

class ParamReader;

/// \brief Plant model and initial state, as read from config/plant/*.yaml (key `plant`).
struct PlantConfig {
  Eigen::MatrixXd A;    ///< state matrix (n x n)
  Eigen::VectorXd B;    ///< input vector (n)
  Eigen::VectorXd B1r;  ///< reference input vector (n)
  Eigen::VectorXd x0;   ///< initial state (n) [e_I rad s, alpha rad, q rad/s]
  int output_index = 1;  ///< y = x[output_index] (alpha)

  int n() const { return static_cast<int>(A.rows()); }
  /// \brief Read the `plant` section; problems go to the reader.
  static PlantConfig read(ParamReader& r, const std::string& prefix = "plant");
  /// \brief Add every problem of the values themselves (sizes, finiteness) to the reader.
  void validate(ParamReader& r, const std::string& prefix = "plant") const;
};

/// \brief The simulation truth: integrates the plant one step with theta, u and r held.
class Plant {
 public:
  explicit Plant(const PlantConfig& cfg);

  /// \brief Advance x by dt [s] with classic RK4; theta, u [rad] and r [rad] constant over the step.
  void step(double dt, const Vec& theta, double u, double r);
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
};

}  // namespace preadaptive_mrac
