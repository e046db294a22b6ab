#pragma once
/// \file robust_config.hpp
/// \brief pa_robust's parameters (key `controller.robust`): owned by the strategy, read and
/// validated here.

#include <string>

namespace preadaptive_mrac {

class ParamReader;

/// \brief Parameters of pa_robust (key `controller.robust`; docs/robust.md).
struct RobustConfig {
  double detect_window = 0.02;    ///< window of the identification residual [s]
  double chunk = 0.005;           ///< data chunk of the verification scores [s]
  double long_window = 0.2;       ///< second, longer residual window (0 = off) [s]
  double threshold = 0.005;       ///< smallest mean residual that triggers [rad]
  double noise_factor = 5.0;      ///< trigger also needs residual > factor x its noise level
  double noise_time = 2.0;        ///< horizon of the noise-level estimate [s]
  double verify_time = 0.05;      ///< decisions are re-made on growing data for this long [s]
  double margin = 0.2;            ///< a candidate must score this fraction below keeping
  double significance = 9.0;      ///< improvements must exceed this many noise variances
  double prior_std = 1.0;         ///< prior spread of theta around the chosen candidate
  double ridge = 1e-2;            ///< floor of the fit's ridge, relative to the data's energy
  double cl_gain = 2.0;           ///< concurrent learning: pull towards the regime's fit [1/s]
  int memory_size = 8;            ///< regimes remembered (least used dropped first)
  double merge_tolerance = 0.02;  ///< regimes closer than this on the visited states merge [rad]
  double settle_time = 1.0;       ///< a regime is banked only after lasting this long [s]
  double quiet_time = 1.0;        ///< phase ends after the residual is quiet this long [s]
  bool use_network = true;        ///< the network's prediction is one of the candidates
  double network_rate = 0.05;     ///< its supervised learning rate at each recovery

  static RobustConfig read(ParamReader& r, const std::string& prefix);
  void validate(ParamReader& r, const std::string& prefix) const;
};

}  // namespace preadaptive_mrac
