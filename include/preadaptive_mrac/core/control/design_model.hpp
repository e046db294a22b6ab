#pragma once
/// \file design_model.hpp
/// \brief The plant as the controller knows it: what the controller, its laws and its
/// strategies are built on. The simulator's configuration (noise, turbulence, servo dynamics,
/// engines) is not part of it; the set-up builds it from the plant's configuration and the
/// controller's optional `controller.model` (designModelOf in closed_loop.hpp).

#include <Eigen/Dense>

#include "preadaptive_mrac/core/elevator_limits.hpp"

namespace preadaptive_mrac {

/// \brief The design model x_dot = A x + B (theta^T x + u) + B1r r, the state it starts
/// from, its output and the elevator limits the controller knows.
struct DesignModel {
  Eigen::MatrixXd A;      ///< state matrix (n x n)
  Eigen::VectorXd B;      ///< elevator input vector (n)
  Eigen::VectorXd B1r;    ///< command input vector (n)
  Eigen::VectorXd x0;     ///< initial state the controller assumes (n)
  int output_index = 1;   ///< index of the output alpha in x
  ElevatorLimits limits;  ///< the elevator's limits (none when not enabled)

  int n() const { return static_cast<int>(A.rows()); }
};

}  // namespace preadaptive_mrac
