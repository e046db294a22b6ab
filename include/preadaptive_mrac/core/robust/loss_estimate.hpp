#pragma once
/// \file loss_estimate.hpp
/// \brief pa_robust's estimate of the loss of elevator effectiveness nu = 1 - Lambda over a
/// regime (robust_preadaptation.hpp, docs/research/robust.md): instrumental variables on blocks of
/// samples between flips of the square-wave excitation.
///
/// With the plant applying Lambda u the data reads y = c^T phi + nu v (v = -u dt - K^T phi).
/// The samples are summed into blocks, one per half-period of the excitation: (Phi, Y, V, D)
/// with D the excitation's integral over the block. The fit is y = c^T Phi + nu V with the
/// instruments (Phi, D): the measurement noise enters u through the feedback and correlates
/// with the noise of y, so least squares on V is biased; the excitation is known and
/// independent of it.

#include <cstdint>
#include <utility>

#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

class LossEstimate {
 public:
  /// \brief For n states; stopped (no blocks collected) and the current block empty.
  explicit LossEstimate(Eigen::Index n = 0);
  /// \brief Start the fit with the blocks that begin at sample start_k or later
  /// (start_k >= 0), or stop it (start_k < 0). Forgets the blocks fitted so far.
  void restart(std::int64_t start_k);
  /// \brief Empty the block being summed (as at time 0, half-period 0).
  void clearBlock();
  /// \brief One sample (phi, y, v) at sample index k in half-period `half` of the
  /// excitation, which contributed d = excitation dt to the command's integral. When `half`
  /// differs from the block's, the block closes and the one before it joins the fit: a block
  /// is added only when the next one closes, so a block a switch reached never is.
  void add(std::int64_t k, std::int64_t half, const Vec& phi, double y, double v, double d);
  /// \brief (nu, information = 1 / variance) for a noise `sigma` of a block sum (endpoint
  /// noise, whatever the block's length); (0, 0) before kMinBlocks blocks or when the
  /// instruments do not determine nu.
  std::pair<double, double> fit(double sigma) const;
  /// \brief Blocks in the fit.
  int blocks() const { return blocks_; }
  static constexpr int kMinBlocks = 4;

 private:
  struct Block {
    Vec phi;
    double y = 0.0, v = 0.0, d = 0.0;
    std::int64_t start_k = 0;
  };
  Eigen::Index n_;
  Block block_, pending_block_;
  bool pending_ = false;
  std::int64_t start_k_ = -1, block_half_ = 0;
  int blocks_ = 0;
  Mat ZX_, ZZ_;  // sums of z x^T and z z^T, z = (Phi, D), x = (Phi, V)
  Vec ZY_;       // sum of z Y
};

}  // namespace preadaptive_mrac
