#pragma once
/// \file types.hpp
/// \brief Eigen types used by the run-time part of the core.
///
/// Run-time vectors and matrices have a dynamic size bounded by a compile-time
/// maximum, so they live on the stack and a controller step never allocates.

#include <Eigen/Dense>

namespace preadaptive_mrac {

/// \brief Largest plant state dimension the run-time types hold.
constexpr int kMaxStates = 8;
/// \brief Largest hidden layer of the preadaptation network.
constexpr int kMaxHidden = 32;
/// \brief Inputs of the preadaptation network: z = [e, |e_dot_est|].
constexpr int kNetInputs = 2;

using Vec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxStates, 1>;
using Mat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxStates, kMaxStates>;
/// \brief Sensitivity S = [d e_v / d theta_hat_I ; d theta_hat / d theta_hat_I] (2n x n).
using SensMat =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 2 * kMaxStates, kMaxStates>;
/// \brief Jacobian Pi of the sensitivity ODE (2n x 2n).
using PiMat =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 2 * kMaxStates, 2 * kMaxStates>;
using HiddenVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxHidden, 1>;
/// \brief Input weights V (2 x h).
using NetV = Eigen::Matrix<double, kNetInputs, Eigen::Dynamic, 0, kNetInputs, kMaxHidden>;
/// \brief Output weights W (h x n).
using NetW = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxHidden, kMaxStates>;
using NetInput = Eigen::Matrix<double, kNetInputs, 1>;

}  // namespace preadaptive_mrac
