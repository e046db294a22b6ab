#pragma once
/// \file small_ops.hpp
/// \brief Reductions of the hot loop written out for three states, with the bits of Eigen's.
///
/// Floating-point sums depend on their order, and every result of the package is reproducible
/// to the last bit (the ROS nodes against the batch CLI, runs against saved outputs). These
/// helpers form each sum in the order Eigen forms it for the run-time sized Vec and Mat of
/// types.hpp, and only skip Eigen's run-time size handling for n = 3 (the B-747 plant); any
/// other size takes Eigen's own expression. test_fast_paths checks the bits against Eigen.

#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

/// \brief For tests: true makes every three-state path of the core (these helpers, Plant::step,
/// SensitivityTracker::accumulate, RobustPreadaptation's window sums and residual) take Eigen's
/// generic expression instead, so whole runs can be compared bit for bit (test_fast_paths).
/// Set it only while no run is going; objects built meanwhile keep their choice (Plant).
inline bool& genericPathsOnly() {
  static bool generic_only = false;
  return generic_only;
}

/// \brief Three entries and no test override: take the written-out path.
inline bool fastThree(Eigen::Index n) { return n == 3 && !genericPathsOnly(); }

/// \brief Ball projection of an estimate onto Omega = {|theta| <= radius}.
inline void clampToBall(Vec* theta, double radius) {
  const double nrm = theta->norm();
  if (nrm > radius) *theta *= radius / nrm;
}

/// \brief a . b. Eigen sums three entries as (a0 b0 + a1 b1) + a2 b2 (a packet of two, then
/// the tail).
inline double dotOf(const Vec& a, const Vec& b) {
  if (fastThree(a.size())) return (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2];
  return a.dot(b);
}

/// \brief y = M x + c r, with M x as Eigen's lazy (coefficient-wise) product: each row summed
/// from column 0 up, then c r added. y may be x.
inline void lazyProductPlus(const Mat& M, const Vec& x, const Vec& c, double r, Vec* y) {
  if (fastThree(x.size()) && M.rows() == 3) {
    const double y0 = ((M(0, 0) * x[0] + M(0, 1) * x[1]) + M(0, 2) * x[2]) + c[0] * r;
    const double y1 = ((M(1, 0) * x[0] + M(1, 1) * x[1]) + M(1, 2) * x[2]) + c[1] * r;
    const double y2 = ((M(2, 0) * x[0] + M(2, 1) * x[1]) + M(2, 2) * x[2]) + c[2] * r;
    y->resize(3);
    (*y)[0] = y0;
    (*y)[1] = y1;
    (*y)[2] = y2;
    return;
  }
  Vec t;
  t.noalias() = M.lazyProduct(x);
  t += c * r;
  *y = t;
}

// Element-wise operations have no order to keep; these only skip the run-time size handling.

/// \brief y = a.
inline void copyTo(const Vec& a, Vec* y) {
  if (fastThree(a.size())) {
    y->resize(3);
    (*y)[0] = a[0];
    (*y)[1] = a[1];
    (*y)[2] = a[2];
  } else {
    *y = a;
  }
}

/// \brief y = a - b.
inline void differenceTo(const Vec& a, const Vec& b, Vec* y) {
  if (fastThree(a.size())) {
    y->resize(3);
    (*y)[0] = a[0] - b[0];
    (*y)[1] = a[1] - b[1];
    (*y)[2] = a[2] - b[2];
  } else {
    *y = a - b;
  }
}

/// \brief y = s a.
inline void scaledTo(double s, const Vec& a, Vec* y) {
  if (fastThree(a.size())) {
    y->resize(3);
    (*y)[0] = s * a[0];
    (*y)[1] = s * a[1];
    (*y)[2] = s * a[2];
  } else {
    *y = s * a;
  }
}

/// \brief y += a.
inline void addTo(const Vec& a, Vec* y) {
  if (fastThree(a.size()) && y->size() == 3) {
    (*y)[0] += a[0];
    (*y)[1] += a[1];
    (*y)[2] += a[2];
  } else {
    *y += a;
  }
}

/// \brief y -= a.
inline void subtractFrom(const Vec& a, Vec* y) {
  if (fastThree(a.size()) && y->size() == 3) {
    (*y)[0] -= a[0];
    (*y)[1] -= a[1];
    (*y)[2] -= a[2];
  } else {
    *y -= a;
  }
}

/// \brief y += s a.
inline void addScaled(double s, const Vec& a, Vec* y) {
  if (fastThree(a.size()) && y->size() == 3) {
    (*y)[0] += s * a[0];
    (*y)[1] += s * a[1];
    (*y)[2] += s * a[2];
  } else {
    *y += s * a;
  }
}

}  // namespace preadaptive_mrac
