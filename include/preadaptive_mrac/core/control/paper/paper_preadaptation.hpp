#pragma once
/// \file paper_preadaptation.hpp
/// \brief The paper's strategies: rac (no reset), pa (reset to the network's theta_hat_I at
/// each onset), pa_learn / pa_learn_exact (and learn from each phase, eqs. perf-pap ..
/// der-E-Vpa, with the approximate or the exact sensitivity).

#include "preadaptive_mrac/core/control/event.hpp"
#include "preadaptive_mrac/core/control/network.hpp"
#include "preadaptive_mrac/core/control/paper/sensitivity_tracker.hpp"
#include "preadaptive_mrac/core/control/preadaptation.hpp"
#include "preadaptive_mrac/core/solvers.hpp"
#include "preadaptive_mrac/params/controller_params.hpp"

namespace preadaptive_mrac {

/// \brief rac, pa, pa_learn, pa_learn_exact: detection by the attention function.
class PaperPreadaptation : public PreadaptationStrategy {
 public:
  /// \brief Which of the paper's four modes.
  enum class Variant { kRac, kPa, kPaLearn, kPaLearnExact };
  PaperPreadaptation(Variant variant, const ControllerParams& cfg, const ControllerDesign& design,
                     const Vec& B, const Vec& PB, int out, PreadaptNetwork* net);
  bool needsTruth() const override { return exact_; }
  const char* truthUse() const override { return exact_ ? "the learning gradient" : ""; }
  std::unique_ptr<PreadaptationStrategy> clone(PreadaptNetwork* net) const override {
    auto c = std::make_unique<PaperPreadaptation>(*this);
    c->net_ = net;
    return c;
  }
  void reset() override { phase_cost_ = 0.0; }
  void onOnset(const Sample& s, Vec* theta_hat, Event* ev) override;
  void duringPhase(const Sample& s, double u, const Vec& theta_hat) override;
  void onRecovery(const Sample& s, const Vec& theta_hat, Event* ev) override;
  double phaseCost() const override { return phase_cost_; }
  const Vec* phaseGradient() const override { return &sens_.grad(); }
  void startExternalPhase() override;
  bool setTunables(const ControllerParams& cfg, const RobustParams& robust) override;

 private:
  bool resets_, learning_, exact_;
  bool projection_;
  double theta_max_, gamma_pa_, dt_;
  PreadaptNetwork* net_;
  SensitivityTracker sens_;
  NetInput z_onset_ = NetInput::Zero();
  Vec theta_err_;
  double phase_cost_ = 0.0;
};

}  // namespace preadaptive_mrac
