#pragma once
/// \file velocity_estimator.hpp
/// \brief The velocity estimator of the output error (docs/spec.md "Attention").

namespace preadaptive_mrac {

/// \brief Dirty derivative s / (tau s + 1) of e, backward-Euler discretised.
class VelocityEstimator {
 public:
  VelocityEstimator(double tau, double dt) : tau_(tau), dt_(dt) {}
  /// \brief Feed one sample; returns the estimate. The first sample gives 0.
  double update(double e);
  double value() const { return value_; }
  void reset() {
    primed_ = false;
    value_ = 0.0;
  }

 private:
  double tau_, dt_;
  bool primed_ = false;
  double prev_ = 0.0, value_ = 0.0;
};

}  // namespace preadaptive_mrac
