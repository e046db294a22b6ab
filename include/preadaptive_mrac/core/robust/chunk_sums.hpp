#pragma once
/// \file chunk_sums.hpp
/// \brief pa_robust's data in chunks (robust_preadaptation.hpp): the sums from which the
/// identification error of any theta follows, and the ridge fit on them, written once for the
/// decision (regime_decision.hpp) and the regime's concurrent learning.

#include "preadaptive_mrac/core/robust/identification_window.hpp"
#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

/// \brief Sums over chunks of the loss regressor V (the chunk's sum of v = -u dt - K^T phi;
/// with the plant applying Lambda u, y = (theta + nu K)^T phi + nu v, nu = 1 - Lambda):
/// V Phi, Y V, V V and V.
struct LossSums {
  Vec hv;
  double yv = 0.0, vv = 0.0, v = 0.0;
};

/// \brief Chunk sums G = sum Phi Phi^T, h = sum Phi Y, c = sum Y^2 (Phi, Y: a chunk's sums
/// of phi and y), so that the identification error of any theta is
/// J = c - 2 theta^T h + theta^T G theta; and, when asked, the loss regressor's sums.
struct ChunkSums {
  Mat G;
  Vec h;
  double c = 0.0;
  LossSums loss;

  /// \brief Zero sums for n states.
  void clear(Eigen::Index n);
  /// \brief Add the chunk of `len` samples from j0 ago; its loss sums too when `with_loss`.
  void add(const IdentificationWindow& win, int j0, int len, bool with_loss);
  /// \brief Weigh every sum so far by f (in (0, 1]: older data counts less).
  void scale(double f);
  /// \brief The identification error J(th) (>= 0).
  double error(const Vec& th) const;
  /// \brief The error of the loop's fixed point th under a loss nu, with the data read as
  /// y = (1 - nu) th^T phi + nu V: J(th) - 2 nu sum (Y - th^T Phi)(V - th^T Phi) + nu^2
  /// sum (V - th^T Phi)^2 (J(th) when nu <= 0).
  double error(const Vec& th, double nu) const;
  /// \brief h as the fixed point under a loss nu sees it: (h - nu sum V Phi) / (1 - nu)
  /// (h when nu <= 0).
  Vec hFixed(double nu) const;
};

/// \brief Bayesian least squares around `base`: base + (G + lambda I)^-1 (h - G base) with
/// lambda = sigma^2 / prior_std^2 + ridge trace(G). Excited directions follow the data,
/// unexcited ones stay at the base.
Vec ridgeFit(const Mat& G, const Vec& h, const Vec& base, double sigma, double prior_std,
             double ridge);

}  // namespace preadaptive_mrac
