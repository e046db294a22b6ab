#pragma once
/// \file jsbsim_linearise.hpp
/// \brief The JSBSim aircraft's short-period model in the package's form x = [e_I, alpha, q],
/// from the coupling itself (preadapt_trim).

#include "preadaptive_mrac/core/types.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_plant.hpp"

namespace preadaptive_mrac {

/// \brief Settings of the linearisation.
struct LineariseOptions {
  double dt = 0.001;            ///< step [s]
  double duration = 6.0;        ///< length of each of the two runs [s]
  double amplitude = 1.745e-3;  ///< elevator amplitude h [rad] (0.1 deg)
};

/// \brief A, B, B1r of x_dot = A x + B u + B1r r at the trim, and how well they fit.
struct LinearModel {
  Mat A;
  Vec B, B1r;
  double residual_alpha = 0.0;                ///< rms of the fit's alphadot residual [rad/s]
  double residual_q = 0.0;                    ///< rms of the qdot residual [rad/s^2]
  double signal_alpha = 0.0, signal_q = 0.0;  ///< rms of what was fitted
};

/// \brief Linearise `plant` (started; trimmed here) by central differences through the
/// coupling: two runs from the trim with the elevator input +h w(t) and -h w(t) (w a doublet,
/// then a 1.7 Hz square wave of half its size), their half difference d = (x+ - x-)/2 (the
/// trim's drift and every even-order term cancel), its time derivative by central differences
/// (d_k+1 - d_k-1) / 2 dt, and a least-squares fit of alphadot and qdot on alpha, q, the
/// elevator, and the speed and pitch-attitude deviations (so the slow mode does not leak into
/// the short period's entries; they are not part of the result). The plant is left trimmed.
LinearModel lineariseJsbsim(JsbsimPlant* plant, const LineariseOptions& opt);

}  // namespace preadaptive_mrac
