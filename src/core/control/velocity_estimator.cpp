#include "preadaptive_mrac/core/control/velocity_estimator.hpp"

namespace preadaptive_mrac {

double VelocityEstimator::update(double e) {
  if (!primed_) {
    primed_ = true;
    prev_ = e;
    value_ = 0.0;
    return value_;
  }
  value_ = (tau_ * value_ + (e - prev_)) / (tau_ + dt_);
  prev_ = e;
  return value_;
}

}  // namespace preadaptive_mrac
