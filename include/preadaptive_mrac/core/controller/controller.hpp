#pragma once
/// \file controller.hpp
/// \brief LQR baseline + MRAC with attention and preadaptation: the controller of Fig. 1.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "preadaptive_mrac/core/control/adaptive_law.hpp"
#include "preadaptive_mrac/core/control/attention.hpp"
#include "preadaptive_mrac/core/control/design_model.hpp"
#include "preadaptive_mrac/core/control/event.hpp"
#include "preadaptive_mrac/core/control/input_guard.hpp"
#include "preadaptive_mrac/core/control/mrac/mrac_law.hpp"
#include "preadaptive_mrac/core/control/network.hpp"
#include "preadaptive_mrac/core/control/preadaptation.hpp"
#include "preadaptive_mrac/core/control/velocity_estimator.hpp"
#include "preadaptive_mrac/core/controller/controller_config.hpp"
#include "preadaptive_mrac/core/solvers.hpp"
#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

/// \brief Input of one controller step.
struct StepInput {
  double t = 0.0;                   ///< sample time [s]
  const Vec* x = nullptr;           ///< measured state [e_I, alpha, q]
  double r = 0.0;                   ///< command [rad]
  const Vec* theta_true = nullptr;  ///< simulation truth; needed by pa_learn_exact only
  /// Elevator the plant applied over [t_{k-1}, t_k] [rad] (PlantState.elevator); null: the
  /// controller's own last answer. pa_robust identifies the plant from it, so a command the
  /// plant did not apply (a stale-timer command in lockstep) must not be taken for it.
  const double* u_applied = nullptr;
};

/// \brief Output of one controller step.
struct StepOutput {
  double u = 0.0;                 ///< elevator command u_bl + u_ad [rad]
  double u_baseline = 0.0;        ///< -K x
  double u_adaptive = 0.0;        ///< -theta_hat^T x + k0 r
  double e = 0.0;                 ///< output error [rad]
  double e_dot = 0.0;             ///< its estimated rate [rad/s]
  double u_unsaturated = 0.0;     ///< u_baseline + u_adaptive before the actuator limits
  bool saturated = false;         ///< u was limited (magnitude or rate)
  Vec x_ref;                      ///< reference-model state at this sample
  Vec theta_hat;                  ///< estimate used for u at this sample (after any reset)
  std::optional<Event> event;     ///< at most one attention event per sample
  bool tunables_applied = false;  ///< tunables queued by setTunables took effect at this sample
};

/// \brief The whole controller: one step per sample, as in Fig. 1 of the paper.
///
/// Per sample t_k with measured x_k: e_v = x_k - x_r; velocity estimate; attention (onset
/// resets theta_hat to the network's theta_hat_I in pa modes; recovery updates the network in
/// learning modes); u = -K x - theta_hat^T x + k0 r; then x_r, theta_hat (Euler, eq.
/// adaptivecontrol) and the sensitivity advance to t_k + dt.
class Controller {
 public:
  /// \brief Derives K (CARE) and P (Lyapunov) from the design model's A, B and the config's
  /// Q, R; throws SolverError when that is impossible. The plant is known only through `model`
  /// (designModelOf in closed_loop.hpp builds it from the plant's and the controller's
  /// configuration).
  Controller(const DesignModel& model, const ControllerConfig& cfg);
  /// \brief The same with K and P already solved: `design` must be designOf(model, cfg)
  /// (RunConfig::design).
  Controller(const DesignModel& model, const ControllerConfig& cfg, const ControllerDesign& design);
  /// \brief K and P of a design model with cfg's Q and R.
  static ControllerDesign designOf(const DesignModel& model, const ControllerConfig& cfg);
  /// \brief A snapshot: the copy has its own network and strategy state.
  Controller(const Controller& other);
  Controller& operator=(const Controller& other);

  /// \brief One sample. Allocation-free.
  StepOutput step(const StepInput& in);
  /// \brief Back to the initial state (x_r, theta_hat, estimator, attention); keeps the network.
  void reset();

  const ControllerDesign& design() const { return design_; }
  const ControllerConfig& config() const { return cfg_; }
  /// \brief The registered mode's name (mode_registry.hpp).
  const std::string& mode() const { return cfg_.mode; }
  const Vec& thetaHat() const { return law_->estimate(); }
  const Vec& xRef() const { return x_r_; }
  bool phaseActive() const { return attention_.phaseActive(); }
  const PreadaptNetwork& network() const { return net_; }
  /// \brief Replace the network (e.g. loaded weights); sizes must match hidden x n.
  void setNetwork(const LearnedState& s);
  /// \brief Start an adaptation phase now, as an onset would, with theta_hat reset to theta_I
  /// (an external trigger; also how a fixed phase is studied). The phase ends at the next
  /// recovery event; learning modes then update the network as usual.
  void startPhase(const Vec& theta_I);
  /// \brief E = integral |e| dt since the phase began [rad s].
  double phaseCost() const { return strategy_->phaseCost(); }
  /// \brief dE/dtheta_hat_I accumulated since the phase began (learning modes; zeros else).
  Vec phaseGradient() const;
  /// \brief The preadaptation strategy of the mode.
  const PreadaptationStrategy& strategy() const { return *strategy_; }
  /// \brief The command while input is stale: the LQR baseline -K x_last (kBaselineHold) or 0,
  /// within the actuator limits. Adaptation, attention and learning do not run.
  double safeCommand(const Vec& x_last, StalePolicy policy);
  /// \brief Queue new tunables; they take effect at the start of the next step() (a step
  /// boundary), which reports it in StepOutput::tunables_applied. Throws ConfigError naming
  /// each offending key (controller.attention.c_ed, ...) when they do not pass
  /// ControllerConfig::validate; nothing is queued then. A later call replaces a queued one.
  void setTunables(const ControllerTunables& t);
  /// \brief The tunables in effect (not a queued change).
  ControllerTunables tunables() const { return ControllerTunables::of(cfg_); }
  bool tunablesPending() const { return pending_.has_value(); }
  /// \brief True in pa_learn_exact and oracle, which need StepInput::theta_true.
  bool needsTruth() const { return strategy_->needsTruth(); }
  /// \brief What the mode uses the true theta for ("" when it does not).
  std::string truthUse() const { return strategy_->truthUse(); }
  /// \brief True when the mode's recoveries change what it keeps (save the weights then).
  bool keepsAtRecovery() const { return strategy_->keepsAtRecovery(); }

 private:
  ControllerConfig cfg_;
  ControllerDesign design_;
  int n_, out_;
  double dt_;
  Vec K_, B_, PB_, b_ref_;
  Mat Phi_r_;  // RK4 transition of the reference model over dt
  Vec Gam_r_;  // RK4 input vector of the reference model over dt (times r)

  Vec x0_, x_r_, ev_;
  // Pseudo-control hedging (cfg_.hedging pch): a second reference model moved also by
  // B (u_limited - u), and the law's error against it. x_r_ stays the unhedged model: e,
  // the attention and every metric are the tracking error of the paper's reference model.
  bool hedge_ = false;
  Vec Gam_b_;  // RK4 input vector of B over dt
  Vec x_h_, ev_h_;
  ElevatorLimits limits_;
  double u_prev_ = 0.0;      // last command sent (the rate limiter's memory; safeCommand too)
  double u_cmd_prev_ = 0.0;  // last answer of step() (what the plant applies in lockstep)
  double r_prev_ = 0.0;
  VelocityEstimator vel_;
  Attention attention_;
  PreadaptNetwork net_;
  std::unique_ptr<AdaptiveLaw> law_;  // owns theta_hat
  // law_ when it is the MRAC law: called without the virtual call (inlined: the hot path of
  // every mode today; 3-5 % of preadapt_sim's time otherwise, docs/design.md)
  MracLaw* mrac_ = nullptr;
  double lawCommand(const LawInput& in) const {
    return mrac_ != nullptr ? mrac_->command(in) : law_->command(in);
  }
  void lawAdvance(const LawInput& in, bool adapt) {
    if (mrac_ != nullptr)
      mrac_->advance(in, adapt);
    else
      law_->advance(in, adapt);
  }
  std::unique_ptr<PreadaptationStrategy> strategy_;
  std::optional<ControllerTunables> pending_;  // queued by setTunables, applied by step()
  void applyTunables(const ControllerTunables& t);
};

}  // namespace preadaptive_mrac
