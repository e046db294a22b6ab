#include "preadaptive_mrac/core/robust/identification_window.hpp"

#include <algorithm>

#include "preadaptive_mrac/core/small_ops.hpp"

namespace preadaptive_mrac {

void IdentificationWindow::resize(int capacity, int long_len, Eigen::Index n) {
  cap_ = capacity;
  long_ = long_len;
  phi_.assign(static_cast<size_t>(cap_), Vec::Zero(n));
  th_.assign(static_cast<size_t>(cap_), Vec::Zero(n));
  y_.assign(static_cast<size_t>(cap_), 0.0);
  v_.assign(static_cast<size_t>(cap_), 0.0);
  phi_long_.setZero(n);
  clear();
}

void IdentificationWindow::clear() {
  head_ = -1;
  count_ = 0;
  phi_long_.setZero();
  y_long_ = 0.0;
  v_long_ = 0.0;
  since_refresh_ = 0;
}

void IdentificationWindow::push(const Vec& phi, double y, const Vec& theta_hat, double v) {
  if (long_ > 0 && count_ >= long_) {  // the sample leaving the long window
    subtractFrom(phi_[static_cast<size_t>(at(long_ - 1))], &phi_long_);
    y_long_ -= y_[static_cast<size_t>(at(long_ - 1))];
    v_long_ -= v_[static_cast<size_t>(at(long_ - 1))];
  }
  head_ = (head_ + 1) % cap_;
  copyTo(phi, &phi_[static_cast<size_t>(head_)]);
  y_[static_cast<size_t>(head_)] = y;
  v_[static_cast<size_t>(head_)] = v;
  copyTo(theta_hat, &th_[static_cast<size_t>(head_)]);
  count_ = std::min(count_ + 1, cap_);
  if (long_ > 0) {
    addTo(phi, &phi_long_);
    y_long_ += y;
    v_long_ += v;
    // Rounding builds up in running sums: sum the window afresh every so often.
    if (++since_refresh_ >= 64 * long_ && count_ >= long_) {
      sums(0, long_, &phi_long_, &y_long_);
      v_long_ = vSum(0, long_);
      since_refresh_ = 0;
    }
  }
}

void IdentificationWindow::sums(int j0, int len, Vec* phi, double* y) const {
  // Newest to oldest, from 0: the order of these sums is part of the results.
  const Eigen::Index n = phi_long_.size();
  phi->setZero(n);
  *y = 0.0;
  if (fastThree(n) && len > 0) {
    // The B-747: three running scalars instead of a run-time sized vector, and the ring index
    // of j + 1 as that of j less one, wrapping (at(j + 1), without its divisions).
    size_t i = static_cast<size_t>(at(j0));
    const size_t last = static_cast<size_t>(cap_) - 1;
    double p0 = 0.0, p1 = 0.0, p2 = 0.0, ys = 0.0;
    for (int c = 0; c < len; ++c) {
      const double* v = phi_[i].data();
      p0 += v[0];
      p1 += v[1];
      p2 += v[2];
      ys += y_[i];
      i = i == 0 ? last : i - 1;
    }
    (*phi)[0] = p0;
    (*phi)[1] = p1;
    (*phi)[2] = p2;
    *y = ys;
    return;
  }
  for (int j = j0; j < j0 + len; ++j) {
    *phi += phi_[static_cast<size_t>(at(j))];
    *y += y_[static_cast<size_t>(at(j))];
  }
}

double IdentificationWindow::vSum(int j0, int len) const {
  double v = 0.0;
  for (int j = j0; j < j0 + len; ++j) v += v_[static_cast<size_t>(at(j))];
  return v;
}

}  // namespace preadaptive_mrac
