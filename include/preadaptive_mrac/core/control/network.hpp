#pragma once
/// \file network.hpp
/// \brief Preadaptation function theta_hat_I = W^T sigma(V^T z), z = [e, |e_dot_est|]
/// (section "Preadaptation Function"), with its gradients (eqs. der-E-Wpa, der-E-Vpa).

#include <cstdint>
#include <vector>

#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

/// \brief One remembered regime (pa_robust's memory, robust/regime_memory.hpp keeps the
/// list bounded): part of what is learned.
struct RegimeEntry {
  Vec theta;                   ///< estimate of theta in the regime
  std::int64_t uses = 0;       ///< times it was stored, merged or recalled
  std::int64_t last_used = 0;  ///< stamp of the last use (larger = more recent)
  /// Loss of elevator effectiveness (1 - Lambda) fitted over the regime's visits, and its
  /// information (1 / variance); 0 and 0 when never fitted.
  double loss = 0.0;
  double loss_info = 0.0;
};

/// \brief What the controller learns and carries from one run to the next, all the weights
/// file holds (io/weights_io.hpp, version 3): the paper's network (its weights, how they were
/// drawn, the episodes learned) and the regimes pa_robust remembers. PreadaptNetwork holds
/// it; the strategies reach the remembered regimes through the network they are given.
struct LearnedState {
  NetV V;                     ///< input weights (2 x h)
  NetW W;                     ///< output weights (h x n)
  std::uint64_t seed = 0;     ///< seed of the initial weights
  double init_scale = 0.0;    ///< initial weights drawn uniform in [-scale, scale]
  std::int64_t episodes = 0;  ///< learning episodes applied so far
  /// Regimes remembered by pa_robust (regime_memory.hpp keeps the list bounded; saved with
  /// the weights, so a second run of the same plant starts with its memory); empty for the
  /// paper's modes.
  std::vector<RegimeEntry> regimes;
  int hidden() const { return static_cast<int>(V.cols()); }
  int outputs() const { return static_cast<int>(W.cols()); }
};

/// \brief Two-layer network without biases, logistic hidden layer (the paper's choice).
class PreadaptNetwork {
 public:
  PreadaptNetwork() = default;
  /// \brief Random weights, uniform in [-scale, scale], from a mt19937_64 seeded with `seed`
  /// (bit-for-bit the same on every platform).
  PreadaptNetwork(int hidden, int outputs, std::uint64_t seed, double scale);
  explicit PreadaptNetwork(const LearnedState& s) : s_(s) {}

  /// \brief theta_hat_I for input z; the hidden activations go to *hidden when given.
  void forward(const NetInput& z, Vec* theta_I, HiddenVec* hidden = nullptr) const;
  /// \brief dE/dW (h x n) and dE/dV (2 x h) at input z for g = dE/dtheta_hat_I.
  void gradients(const NetInput& z, const Vec& g, NetW* dW, NetV* dV) const;
  /// \brief One learning step: W -= rate dE/dW, V -= rate dE/dV (eq. learn-alg-pap);
  /// both gradients use the weights before the step.
  void learn(const NetInput& z, const Vec& g, double rate);

  const LearnedState& state() const { return s_; }
  LearnedState& state() { return s_; }
  int hidden() const { return s_.hidden(); }
  int outputs() const { return s_.outputs(); }

 private:
  LearnedState s_;
};

}  // namespace preadaptive_mrac
