#include "preadaptive_mrac/core/robust/regime_decision.hpp"

#include <algorithm>
#include <cmath>

namespace preadaptive_mrac {

DecisionResult decideRegime(const DecisionData& data, const DecisionCandidates& cand,
                            const DecisionSettings& s) {
  const ChunkSums& cs = data.chunks;
  const double sigma = s.sigma;
  const double z = s.z;
  // A candidate beats keeping when its error is `margin` lower and the gain is beyond what
  // noise explains: if keeping were right, J_keep - J_cand = -D + 2 sum d_i eps_i with
  // d_i = (cand - keep)^T Phi_i and D = sum d_i^2, so noise alone gives 2 sigma sqrt(D).
  const double j_keep = cs.error(cand.keep);
  auto beats = [&](const Vec& th, double jc) {
    const Vec d = th - cand.keep;
    const double D = std::max(0.0, d.dot(cs.G * d));
    return jc < (1.0 - s.margin) * j_keep && j_keep - jc > z * 2.0 * sigma * std::sqrt(D);
  };
  DecisionResult res;
  res.error_keep = j_keep;
  Event::Decision& kind = res.kind;
  double j_best = j_keep;
  Vec base = cand.keep;
  res.candidates = 1;
  for (size_t i = 0; i < cand.memory.size(); ++i, ++res.candidates) {
    const double nui = cand.memory_loss[i];
    const double ji = cs.error(cand.memory[i], nui);
    if (ji < j_best && beats(cand.memory[i], ji)) {
      j_best = ji;
      kind = Event::Decision::kMemory;
      res.chosen = static_cast<int>(i);
      base = cand.memory[i];
      res.nu = nui;
    }
  }
  if (cand.use_network) {
    ++res.candidates;
    const double jn = cs.error(cand.network);
    if (jn < j_best && beats(cand.network, jn)) {
      j_best = jn;
      kind = Event::Decision::kNetwork;
      res.chosen = -1;
      base = cand.network;
      res.nu = 0.0;
    }
  }
  const double nu = res.nu;
  // Fit what the data determines around the chosen base; with a recalled loss the fit and the
  // mean below aim at the fixed point: (Y - nu V) / (1 - nu).
  Vec fitted = ridgeFit(cs.G, cs.hFixed(nu), base, sigma, s.prior_std, s.ridge);
  const double j_fit = cs.error(fitted, nu);
  // The fit moves the base only when the base's mean mismatch over all post-change data,
  // |sum Y - base^T sum Phi|, is beyond z standard deviations: the total's noise is endpoint
  // noise only (the sums telescope). So noise moves nothing, and a recalled regime that
  // explains the data is used as remembered.
  const Vec& phi_tot = data.phi_tot;
  double y_tot = data.y_tot;
  if (nu > 0.0) y_tot = (y_tot - nu * cs.loss.v) / (1.0 - nu);
  if (std::abs(y_tot - base.dot(phi_tot)) > z * sigma && j_fit < j_best) {
    if (kind == Event::Decision::kKeep) kind = Event::Decision::kFit;
  } else {
    fitted = base;
  }
  // Minimum change along the data. What the post-change data determines best is the mean
  // mismatch, y_tot - theta^T phi_tot, yet early on its noise (that of two end samples over a
  // few ms) is tens of mrad of elevator: a candidate that fits the data no worse than noise
  // explains, or the fit itself, can over-compensate, a spike of the elevator. So while the
  // decisions are re-made, theta^T phi_tot moves from keeping towards the data only: the first
  // move no further than the data proves (the near end of its z-interval), later ones no
  // further than its mean; never the other way. The other directions keep what the candidate
  // and the fit say. The last decision, on verify_time of data, sets the estimate unclipped,
  // so the regime fit does not start from the clipped one.
  const double pp = phi_tot.squaredNorm();
  if (kind != Event::Decision::kKeep && pp > 0.0 && s.clip) {
    const double vk = cand.keep.dot(phi_tot);
    const double sgn = y_tot >= vk ? 1.0 : -1.0;
    const double kappa = s.first_move ? z : 0.0;
    const double reach = std::max(0.0, sgn * (y_tot - vk) - kappa * sigma);
    const double move = sgn * (fitted.dot(phi_tot) - vk);
    const double target = std::min(std::max(move, 0.0), reach);
    if (target != move) fitted += sgn * (target - move) / pp * phi_tot;
  }
  res.theta = fitted;
  return res;
}

}  // namespace preadaptive_mrac
