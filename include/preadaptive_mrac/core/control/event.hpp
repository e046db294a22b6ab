#pragma once
/// \file event.hpp
/// \brief An attention event as the controller reports it (onsets, recoveries, decisions).

#include <cstdint>

#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

/// \brief An attention event.
struct Event {
  enum class Type { kOnset, kRecovered, kIgnoredOnset, kIgnoredRecovery, kDecision };
  /// \brief What a verification (pa_robust) chose.
  enum class Decision { kNone, kKeep, kFit, kMemory, kNetwork };
  Type type = Type::kOnset;
  double t = 0.0;             ///< sample time [s]
  double e = 0.0;             ///< output error alpha - alpha_r [rad]
  double e_dot = 0.0;         ///< estimated rate of e [rad/s]
  Vec theta_hat_before;       ///< estimate before the event
  Vec theta_hat_after;        ///< estimate after (the reset value on onsets in pa modes)
  bool reset = false;         ///< theta_hat was reset to theta_hat_I
  double cost = 0.0;          ///< E = integral |e| dt over the phase (recoveries)
  Vec grad;                   ///< dE/dtheta_hat_I (recoveries in learning modes)
  bool learned = false;       ///< the network was updated
  std::int64_t episodes = 0;  ///< learning episodes after the event
  // pa_robust verification (onsets and decisions):
  Decision decision = Decision::kNone;  ///< keep, fit the data, a remembered regime, network
  int chosen = -1;                      ///< index of the remembered regime chosen (kMemory)
  int candidates = 0;                   ///< candidates scored (keep, memory, network)
  double score = 0.0;       ///< RMS identification residual of the estimate kept or set [rad]
  double score_keep = 0.0;  ///< the same for keeping the pre-switch estimate [rad]
};
const char* eventTypeName(Event::Type t);
const char* decisionName(Event::Decision d);

}  // namespace preadaptive_mrac
