#include "preadaptive_mrac/core/sim/actuator.hpp"

#include <cmath>
#include <stdexcept>

namespace preadaptive_mrac {

TransportDelay::TransportDelay(std::int64_t steps) {
  if (steps < 0) throw std::invalid_argument("TransportDelay: steps must be >= 0");
  buf_.assign(static_cast<size_t>(steps), 0.0);
}

std::int64_t TransportDelay::stepsFor(double delay, double dt) {
  return static_cast<std::int64_t>(std::llround(delay / dt));
}

double TransportDelay::push(double u) {
  if (buf_.empty()) return u;
  const double out = buf_[head_];
  buf_[head_] = u;
  head_ = head_ + 1 == buf_.size() ? 0 : head_ + 1;
  return out;
}

void TransportDelay::reset() {
  std::fill(buf_.begin(), buf_.end(), 0.0);
  head_ = 0;
}

ServoLag::ServoLag(double time_constant, double dt) {
  if (!(time_constant >= 0.0) || !(dt > 0.0))
    throw std::invalid_argument("ServoLag: time constant must be >= 0 and dt > 0");
  active_ = time_constant > 0.0;
  // -expm1(-x) = 1 - exp(-x) without the cancellation of a small x (T >> dt).
  if (active_) alpha_ = -std::expm1(-dt / time_constant);
}

double ServoLag::step(double u) {
  if (!active_) return u;
  y_ += alpha_ * (u - y_);
  return y_;
}

ActuatorChain::ActuatorChain(const ActuatorDynamics& dyn, const ActuatorLimits& limits, double dt)
    : delay_(TransportDelay::stepsFor(dyn.delay, dt)),
      lag_(dyn.time_constant, dt),
      limits_(limits),
      dt_(dt) {
  identity_ = delay_.steps() == 0 && !lag_.active() && !limits_.enabled;
}

double ActuatorChain::applyChain(double u) {
  const double v = lag_.step(delay_.push(u));
  const double a = limits_.apply(v, applied_, dt_);
  limited_ = a != v;
  applied_ = a;
  return a;
}

void ActuatorChain::reset() {
  delay_.reset();
  lag_.reset();
  limited_ = false;
  applied_ = 0.0;
}

}  // namespace preadaptive_mrac
