#include "preadaptive_mrac/core/control/oracle/oracle_preadaptation.hpp"

#include <cmath>

#include "preadaptive_mrac/core/control/attention.hpp"
#include "preadaptive_mrac/core/control/mode_context.hpp"
#include "preadaptive_mrac/params/controller_params.hpp"

namespace preadaptive_mrac {

Detection OraclePreadaptation::detect(const Sample& s, const Vec& theta_hat, Attention* attention) {
  (void)theta_hat;
  (void)attention;
  // The truth changes exactly at a switch; anything else is not an event for the oracle.
  if (have_last_ && *s.theta_true == last_) return Detection::kNone;
  have_last_ = true;
  last_ = *s.theta_true;
  return Detection::kOnset;
}

void OraclePreadaptation::onOnset(const Sample& s, Vec* theta_hat, Event* ev) {
  phase_cost_ = 0.0;
  *theta_hat = *s.theta_true;
  ev->reset = true;
}

// The phase cost only (no learning): E = integral |e| dt, reported at the recovery.
void OraclePreadaptation::duringPhase(const Sample& s, double /*u*/, const Vec& /*theta_hat*/) {
  phase_cost_ += std::abs(s.e) * dt_;
}

void OraclePreadaptation::onRecovery(const Sample& /*s*/, const Vec& /*theta_hat*/, Event* ev) {
  ev->cost = phase_cost_;
}

std::unique_ptr<PreadaptationStrategy> makeOraclePreadaptation(const ModeContext& m) {
  return std::make_unique<OraclePreadaptation>(m.cfg->sample_time);
}

}  // namespace preadaptive_mrac
