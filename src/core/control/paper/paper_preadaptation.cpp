#include "preadaptive_mrac/core/control/paper/paper_preadaptation.hpp"

#include <cmath>

#include "preadaptive_mrac/core/control/attention.hpp"
#include "preadaptive_mrac/core/small_ops.hpp"

namespace preadaptive_mrac {

Detection PreadaptationStrategy::detect(const Sample& s, const Vec& theta_hat,
                                        Attention* attention) {
  (void)theta_hat;
  switch (attention->update(s.e, s.e_dot)) {
    case Attention::Result::kOnset:
      return Detection::kOnset;
    case Attention::Result::kRecovered:
      return Detection::kRecovered;
    case Attention::Result::kIgnoredOnset:
      return Detection::kIgnoredOnset;
    case Attention::Result::kIgnoredRecovery:
      return Detection::kIgnoredRecovery;
    case Attention::Result::kNone:
      break;
  }
  return Detection::kNone;
}

void PreadaptationStrategy::onDecision(const Sample& s, Vec* theta_hat, Event* ev) {
  (void)s;
  (void)theta_hat;
  (void)ev;
}

PaperPreadaptation::PaperPreadaptation(Variant mode, const ControllerParams& cfg,
                                       const ControllerDesign& design, const Vec& B, const Vec& PB,
                                       int out, PreadaptNetwork* net)
    : resets_(mode != Variant::kRac),
      learning_(mode == Variant::kPaLearn || mode == Variant::kPaLearnExact),
      exact_(mode == Variant::kPaLearnExact),
      projection_(cfg.projection),
      theta_max_(cfg.theta_max),
      gamma_pa_(cfg.gamma_pa),
      dt_(cfg.sample_time),
      net_(net),
      sens_(design.Ar, B, PB, cfg.gamma, out) {
  theta_err_.setZero(B.size());
}

void PaperPreadaptation::onOnset(const Sample& s, Vec* theta_hat, Event* ev) {
  phase_cost_ = 0.0;
  if (!resets_) return;
  z_onset_ << s.e, std::abs(s.e_dot);
  net_->forward(z_onset_, theta_hat);
  if (projection_) clampToBall(theta_hat, theta_max_);
  ev->reset = true;
  if (learning_) sens_.start();
}

void PaperPreadaptation::duringPhase(const Sample& s, double u, const Vec& theta_hat) {
  (void)u;
  phase_cost_ += std::abs(s.e) * dt_;
  if (!learning_) return;
  if (exact_)
    theta_err_ = *s.theta_true - theta_hat;
  else
    theta_err_.setZero();
  sens_.accumulate(dt_, *s.ev, *s.x, theta_err_);
}

void PaperPreadaptation::onRecovery(const Sample& s, const Vec& theta_hat, Event* ev) {
  (void)s;
  (void)theta_hat;
  ev->cost = phase_cost_;
  if (!learning_) return;
  ev->grad = sens_.grad();
  net_->learn(z_onset_, sens_.grad(), gamma_pa_);
  ev->learned = true;
}

bool PaperPreadaptation::setTunables(const ControllerParams& cfg, const RobustParams& /*robust*/) {
  projection_ = cfg.projection;
  theta_max_ = cfg.theta_max;
  gamma_pa_ = cfg.gamma_pa;
  sens_.setGamma(cfg.gamma);
  return false;
}

void PaperPreadaptation::startExternalPhase() {
  phase_cost_ = 0.0;
  z_onset_.setZero();
  sens_.start();
}

}  // namespace preadaptive_mrac
