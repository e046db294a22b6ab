#include "preadaptive_mrac/core/robust/loss_estimate.hpp"

#include <algorithm>
#include <cmath>

namespace preadaptive_mrac {

LossEstimate::LossEstimate(Eigen::Index n) : n_(n) {
  block_.phi.setZero(n);
  pending_block_.phi.setZero(n);
  restart(-1);
}

void LossEstimate::restart(std::int64_t start_k) {
  start_k_ = start_k;
  ZX_.setZero(n_ + 1, n_ + 1);
  ZZ_.setZero(n_ + 1, n_ + 1);
  ZY_.setZero(n_ + 1);
  pending_ = false;
  blocks_ = 0;
}

void LossEstimate::clearBlock() {
  block_.phi.setZero(n_);
  block_.y = block_.v = block_.d = 0.0;
  block_.start_k = 0;
  block_half_ = 0;
}

void LossEstimate::add(std::int64_t k, std::int64_t half, const Vec& phi, double y, double v,
                       double d) {
  if (half != block_half_) {  // a flip: the block closes, the one before it joins the fit
    if (pending_) {
      Vec z(n_ + 1), x(n_ + 1);
      z << pending_block_.phi, pending_block_.d;
      x << pending_block_.phi, pending_block_.v;
      ZX_.noalias() += z * x.transpose();
      ZZ_.noalias() += z * z.transpose();
      ZY_ += pending_block_.y * z;
      ++blocks_;
    }
    pending_ = start_k_ >= 0 && block_.start_k >= start_k_;
    std::swap(pending_block_, block_);
    block_.phi.setZero(n_);
    block_.y = block_.v = block_.d = 0.0;
    block_.start_k = k;
    block_half_ = half;
  }
  block_.phi += phi;
  block_.y += y;
  block_.v += v;
  block_.d += d;
}

std::pair<double, double> LossEstimate::fit(double sigma) const {
  if (blocks_ < kMinBlocks) return {0.0, 0.0};
  const Eigen::Index n = n_;
  Mat A = ZX_;
  const double ridge = 1e-12 * std::max(ZX_.topLeftCorner(n, n).trace(), 0.0);
  for (Eigen::Index i = 0; i < n; ++i) A(i, i) += ridge;
  const auto lu = A.fullPivLu();
  if (!lu.isInvertible()) return {0.0, 0.0};
  const Mat Ai = lu.inverse();
  const Vec beta = Ai * ZY_;
  const double var = sigma * sigma * (Ai * ZZ_ * Ai.transpose())(n, n);
  if (!(var > 0.0) || !std::isfinite(beta[n])) return {0.0, 0.0};
  return {beta[n], 1.0 / var};
}

}  // namespace preadaptive_mrac
