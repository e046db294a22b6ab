#include "preadaptive_mrac/core/control/paper/sensitivity_tracker.hpp"

#include <cmath>

#include "preadaptive_mrac/core/small_ops.hpp"

namespace preadaptive_mrac {

SensitivityTracker::SensitivityTracker(const Mat& Ar, const Vec& B, const Vec& PB, double gamma,
                                       int out)
    : Ar_(Ar), B_(B), PB_(PB), gamma_(gamma), out_(out), n_(static_cast<int>(Ar.rows())) {
  S_.setZero(2 * n_, n_);
  Sdot_.setZero(2 * n_, n_);
  g_.setZero(n_);
}

void SensitivityTracker::start() {
  S_.setZero(2 * n_, n_);
  S_.bottomRows(n_).setIdentity();
  E_ = 0.0;
  g_.setZero(n_);
}

PiMat SensitivityTracker::pi(const Vec& ev, const Vec& x, const Vec& theta_err) const {
  PiMat P = PiMat::Zero(2 * n_, 2 * n_);
  P.topLeftCorner(n_, n_) = Ar_ + B_ * theta_err.transpose();
  P.topRightCorner(n_, n_) = -B_ * x.transpose();
  P.bottomLeftCorner(n_, n_) =
      gamma_ * ev.dot(PB_) * Mat::Identity(n_, n_) + gamma_ * x * PB_.transpose();
  return P;
}

void SensitivityTracker::accumulate(double dt, const Vec& ev, const Vec& x, const Vec& theta_err) {
  const double e = ev[out_];
  E_ += std::abs(e) * dt;
  const double sgn = (e > 0.0) - (e < 0.0);
  if (fastThree(n_)) {
    accumulate3(dt, sgn, ev, x, theta_err);
    return;
  }
  g_ += (sgn * dt) * S_.row(out_).transpose();
  // S_dot = Pi S without forming Pi: the blocks are rank-one updates of A_r and the identity.
  const auto top = S_.topRows(n_);
  const auto bot = S_.bottomRows(n_);
  Eigen::Matrix<double, 1, Eigen::Dynamic, Eigen::RowMajor, 1, kMaxStates> row1, row2, row3;
  row1.noalias() = theta_err.transpose().lazyProduct(top);
  row2.noalias() = x.transpose().lazyProduct(bot);
  row3.noalias() = PB_.transpose().lazyProduct(top);
  Sdot_.topRows(n_).noalias() = Ar_.lazyProduct(top);
  Sdot_.topRows(n_).noalias() += B_ * (row1 - row2);
  Sdot_.bottomRows(n_) = (gamma_ * ev.dot(PB_)) * top;
  Sdot_.bottomRows(n_).noalias() += gamma_ * x * row3;
  S_ += dt * Sdot_;
}

// accumulate() written out for three states, each sum in the order of Eigen's expressions
// above (test_fast_paths compares the two): the lazy products summed from index 0 up, the
// outer products added after them, B_i (row1 - row2)_j and row3_j (gamma x_i).
void SensitivityTracker::accumulate3(double dt, double sgn, const Vec& ev, const Vec& x,
                                     const Vec& theta_err) {
  const double c = sgn * dt;
  for (int j = 0; j < 3; ++j) g_[j] += c * S_(out_, j);
  double row1[3], row2[3], row3[3];
  for (int j = 0; j < 3; ++j) {
    row1[j] = (theta_err[0] * S_(0, j) + theta_err[1] * S_(1, j)) + theta_err[2] * S_(2, j);
    row2[j] = (x[0] * S_(3, j) + x[1] * S_(4, j)) + x[2] * S_(5, j);
    row3[j] = (PB_[0] * S_(0, j) + PB_[1] * S_(1, j)) + PB_[2] * S_(2, j);
  }
  const double ce = gamma_ * dotOf(ev, PB_);
  const double gx[3] = {gamma_ * x[0], gamma_ * x[1], gamma_ * x[2]};
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      Sdot_(i, j) = ((Ar_(i, 0) * S_(0, j) + Ar_(i, 1) * S_(1, j)) + Ar_(i, 2) * S_(2, j)) +
                    B_[i] * (row1[j] - row2[j]);
      Sdot_(3 + i, j) = ce * S_(i, j) + row3[j] * gx[i];
    }
  }
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 6; ++i) S_(i, j) += dt * Sdot_(i, j);
}

}  // namespace preadaptive_mrac
