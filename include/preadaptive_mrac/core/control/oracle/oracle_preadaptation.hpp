#pragma once
/// \file oracle_preadaptation.hpp
/// \brief `oracle`: a simulation-only yardstick. At every change of the true theta (and at the
/// first sample) theta_hat is set to the true theta, instantly; the MRAC law runs as usual.
/// Needs the truth (like pa_learn_exact), so it cannot run on a real aircraft.

#include "preadaptive_mrac/core/control/event.hpp"
#include "preadaptive_mrac/core/control/preadaptation.hpp"

namespace preadaptive_mrac {

class OraclePreadaptation : public PreadaptationStrategy {
 public:
  explicit OraclePreadaptation(double dt) : dt_(dt) {}
  std::unique_ptr<PreadaptationStrategy> clone(PreadaptNetwork* net) const override {
    (void)net;
    return std::make_unique<OraclePreadaptation>(*this);
  }
  bool needsTruth() const override { return true; }
  const char* truthUse() const override { return "theta_hat := theta at each switch"; }
  bool constrainsEvents() const override { return true; }
  void reset() override {
    have_last_ = false;
    phase_cost_ = 0.0;
  }
  Detection detect(const Sample& s, const Vec& theta_hat, Attention* attention) override;
  void onOnset(const Sample& s, Vec* theta_hat, Event* ev) override;
  void duringPhase(const Sample& s, double u, const Vec& theta_hat) override;
  void onRecovery(const Sample& s, const Vec& theta_hat, Event* ev) override;
  double phaseCost() const override { return phase_cost_; }

 private:
  double dt_;
  bool have_last_ = false;
  Vec last_;
  double phase_cost_ = 0.0;
};

struct ModeContext;
/// \brief The registry's factory (mode_registry.hpp).
std::unique_ptr<PreadaptationStrategy> makeOraclePreadaptation(const ModeContext& m);

}  // namespace preadaptive_mrac
