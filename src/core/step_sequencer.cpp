#include "preadaptive_mrac/core/step_sequencer.hpp"

#include <algorithm>
#include <cmath>

namespace preadaptive_mrac {

StepSequencer::StepSequencer(Controller* ctl, int n, double sample_time, double stale_timeout,
                             StalePolicy policy)
    : ctl_(ctl),
      n_(n),
      sample_time_(sample_time),
      policy_(policy),
      guard_(static_cast<std::size_t>(n), stale_timeout),
      x_(n),
      x_last_valid_(Vec::Zero(n)) {}

bool StepSequencer::sequence(const PlantSample& s, SampleOutcome* o) {
  if (have_last_) {
    if (s.step < last_step_) {
      // A new plant run: a restarted plant (whose first states may have gone out before this
      // controller was connected again).
      o->restarted_after = last_step_;
      ctl_->reset();
      ++restarts_;
      safe_step_ = 0;
      last_valid_step_ = 0;
    } else if (s.step == last_step_) {
      return false;  // the controller does not step twice
    } else if (s.step != last_step_ + 1) {
      gaps_ += 1;
      o->missing = std::make_pair(last_step_ + 1, s.step - 1);
    }
  }
  have_last_ = true;
  last_step_ = s.step;
  return true;
}

SampleOutcome StepSequencer::onSample(const PlantSample& s, const Vec* theta, double refresh,
                                      double now) {
  SampleOutcome o;
  if (!dt_checked_) {
    if (std::abs(s.dt - sample_time_) > 1e-12 * std::max(1.0, sample_time_)) {
      o.kind = SampleOutcome::Kind::kBadSampleTime;
      return o;
    }
    dt_checked_ = true;
  }
  if (!sequence(s, &o)) {
    o.kind = SampleOutcome::Kind::kRepeated;
    return o;
  }
  if (!guard_.accept(refresh, s.x, s.size, &o.why, "x")) {
    o.kind = SampleOutcome::Kind::kRejected;
    return o;
  }
  ++steps_;
  last_valid_step_ = s.step;
  last_valid_t_ = s.t;
  // The plant's last step: the silence after it is the end of the run, not stale input.
  const bool last = s.total_steps > 0 && s.step + 1 >= s.total_steps;
  o.finished = last && !run_over_;
  run_over_ = last;
  if (stale_) {
    stale_ = false;
    o.stale_for = now - stale_since_;
  }
  for (int i = 0; i < n_; ++i) x_[i] = s.x[i];
  x_last_valid_ = x_;
  StepInput in;
  in.t = s.t;
  in.x = &x_;
  in.r = s.r;
  in.theta_true = theta;
  // The elevator the plant applied over the last step (rate- and magnitude-limited, or the
  // plant's hold): pa_robust identifies from it, as the batch loop does.
  if (std::isfinite(s.elevator)) in.u_applied = &s.elevator;
  try {
    o.out = ctl_->step(in);
  } catch (const std::exception& e) {
    o.kind = SampleOutcome::Kind::kStepFailed;
    o.why = e.what();
  }
  return o;
}

std::optional<StaleTick> StepSequencer::onTimer(double now) {
  // Before the first valid state there is nothing to hold (and no plant to command).
  if (!guard_.haveValid() || !guard_.stale(now) || run_over_) return std::nullopt;
  StaleTick tick;
  if (!stale_) {
    stale_ = true;
    ++stale_episodes_;
    stale_since_ = now;
    safe_step_ = std::max(safe_step_, last_step_);
    tick.began = true;
  }
  // No controller step: theta_hat, attention and learning stay as they are.
  safe_step_ = std::max(safe_step_ + 1, last_step_ + 1);
  tick.step = safe_step_;
  tick.t = last_valid_t_ + static_cast<double>(safe_step_ - last_valid_step_) * sample_time_;
  return tick;
}

}  // namespace preadaptive_mrac
