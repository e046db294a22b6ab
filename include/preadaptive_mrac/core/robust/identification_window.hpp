#pragma once
/// \file identification_window.hpp
/// \brief pa_robust's identification data (robust_preadaptation.hpp): a ring of the last
/// samples (phi_k, y_k, theta_hat_k, v_k) with window sums, and running sums over a long window.

#include <vector>

#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

class IdentificationWindow {
 public:
  /// \brief `capacity` samples of n states; running sums over the newest `long_len` (0: none).
  /// Empties the ring.
  void resize(int capacity, int long_len, Eigen::Index n);
  /// \brief Empty the ring and the running sums (keeps the sizes).
  void clear();
  /// \brief Ring index of the sample j samples ago (0 = newest).
  int at(int j) const { return ((head_ - j) % cap_ + cap_) % cap_; }
  /// \brief Add the newest sample; v is its loss regressor (robust_preadaptation.hpp).
  void push(const Vec& phi, double y, const Vec& theta_hat, double v);
  /// \brief Sums of phi and y over `len` samples from j0 samples ago, newest first (the order
  /// is part of the results).
  void sums(int j0, int len, Vec* phi, double* y) const;
  /// \brief Samples held (at most the capacity).
  int count() const { return count_; }
  const Vec& phi(int i) const { return phi_[static_cast<size_t>(i)]; }
  double y(int i) const { return y_[static_cast<size_t>(i)]; }
  const Vec& theta(int i) const { return th_[static_cast<size_t>(i)]; }
  /// \brief Sum of v over `len` samples from j0 samples ago, newest first.
  double vSum(int j0, int len) const;
  /// \brief Running sums over the newest long_len samples.
  const Vec& phiLong() const { return phi_long_; }
  double yLong() const { return y_long_; }
  double vLong() const { return v_long_; }
  double v(int i) const { return v_[static_cast<size_t>(i)]; }

 private:
  std::vector<Vec> phi_, th_;
  std::vector<double> y_, v_;
  int head_ = -1, count_ = 0, cap_ = 1, long_ = 0;
  Vec phi_long_;
  double y_long_ = 0.0, v_long_ = 0.0;
  int since_refresh_ = 0;
};

}  // namespace preadaptive_mrac
