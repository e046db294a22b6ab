#pragma once
/// \file regime_decision.hpp
/// \brief pa_robust's decision (robust_preadaptation.hpp, docs/research/robust.md) as a pure
/// function: from the post-change data's sums and the candidates (keep the pre-switch estimate, the
/// remembered regimes, the network's prediction) to the estimate to set. No state: a decision
/// seen in a run can be replayed from its numbers (test_robust).

#include <vector>

#include "preadaptive_mrac/core/control/event.hpp"
#include "preadaptive_mrac/core/robust/chunk_sums.hpp"

namespace preadaptive_mrac {

/// \brief The post-change data: its chunk sums (with the loss sums when a candidate carries a
/// loss), and the plain sums of phi and y over all of it.
struct DecisionData {
  ChunkSums chunks;
  Vec phi_tot;
  double y_tot = 0.0;
};

/// \brief What may be chosen: `keep` (the estimate before the switch), each remembered
/// regime's theta with the loss it carries (0: none), and the network's prediction.
struct DecisionCandidates {
  Vec keep;
  std::vector<Vec> memory;
  std::vector<double> memory_loss;
  bool use_network = false;
  Vec network;
};

/// \brief The decision's settings: the noise of a chunk sum `sigma` [rad s], `z` standard
/// deviations for significance, and controller.robust's margin, prior_std and ridge.
/// `first_move`: no decision since the onset has moved the estimate; `clip`: the decision is
/// re-made later (before verify_time), so the mean mismatch moves only as far as the data
/// proves.
struct DecisionSettings {
  double sigma = 0.0, z = 0.0, margin = 0.0, prior_std = 0.0, ridge = 0.0;
  bool first_move = false, clip = false;
};

struct DecisionResult {
  Event::Decision kind = Event::Decision::kKeep;
  int chosen = -1;          ///< index of the remembered regime (kMemory), else -1
  int candidates = 0;       ///< candidates scored
  Vec theta;                ///< the estimate to set (the keep estimate when kKeep)
  double nu = 0.0;          ///< the loss the chosen candidate carries
  double error_keep = 0.0;  ///< identification error of keeping
};

/// \brief Score every candidate on the data, take the best that beats keeping beyond noise,
/// fit what the data determines around it, and limit the move along the data
/// (docs/research/robust.md).
DecisionResult decideRegime(const DecisionData& data, const DecisionCandidates& cand,
                            const DecisionSettings& s);

}  // namespace preadaptive_mrac
