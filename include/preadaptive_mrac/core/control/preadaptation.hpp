#pragma once
/// \file preadaptation.hpp
/// \brief The one interface every preadaptation strategy implements: how a disturbance is
/// detected, what happens at an onset, during a phase and at a recovery.
///
/// Controller::step has one path for every mode: detect, act on the detection through the
/// strategy, compute u, let the strategy follow the phase, run the adaptation law. A new
/// strategy is a new folder with a class behind this interface (paper/paper_preadaptation.hpp:
/// rac, pa, pa_learn, pa_learn_exact; oracle/oracle_preadaptation.hpp: oracle;
/// core/robust/robust_preadaptation.hpp: pa_robust).

#include <memory>
#include <optional>

#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

class Attention;
struct Event;
struct ControllerParams;
struct RobustParams;
struct ControllerDesign;
class PreadaptNetwork;
class RegimeMemory;

/// \brief What a strategy sees of one sample t_k.
struct Sample {
  double t = 0.0;                   ///< sample time [s]
  const Vec* x = nullptr;           ///< measured state x_k [e_I, alpha, q]
  double r = 0.0;                   ///< command r(t_k) [rad]
  const Vec* theta_true = nullptr;  ///< simulation truth (strategies that need it only)
  const Vec* ev = nullptr;          ///< e_v = x - x_r
  double e = 0.0;                   ///< output error [rad]
  double e_dot = 0.0;               ///< its estimated rate [rad/s]
  double u_prev = 0.0;              ///< elevator applied over [t_{k-1}, t_k] [rad]
  double r_prev = 0.0;              ///< r held over [t_{k-1}, t_k] [rad]
};

/// \brief What a sample's detection found.
enum class Detection {
  kNone,
  kOnset,            ///< a disturbance began: start a phase (onOnset)
  kRecovered,        ///< the phase ended (onRecovery)
  kIgnoredOnset,     ///< an onset inside an active phase (reported only)
  kIgnoredRecovery,  ///< a recovery outside a phase (reported only)
  kDecision,         ///< a strategy's own decision inside a phase (onDecision)
};

/// \brief A preadaptation strategy. The controller owns the attention function, the network
/// and the regime memory and hands them over; the strategy owns its own phase state.
class PreadaptationStrategy {
 public:
  virtual ~PreadaptationStrategy() = default;
  /// \brief A copy with the same state, using `net` as its network (Controller's copy).
  virtual std::unique_ptr<PreadaptationStrategy> clone(PreadaptNetwork* net) const = 0;
  /// \brief True when the strategy needs Sample::theta_true (a simulation-only mode).
  virtual bool needsTruth() const { return false; }
  /// \brief What the true theta is used for, for the console when needsTruth() ("" else).
  virtual const char* truthUse() const { return ""; }
  /// \brief True when a recovery changes what the strategy keeps beyond a run (the network
  /// it trains at recovery, the regimes it remembers): a node saves its weights then.
  virtual bool keepsAtRecovery() const { return false; }
  /// \brief True when the estimate an event leaves must be brought back into the law's set
  /// (AdaptiveLaw::constrain). The paper's modes reset as the paper does, unprojected.
  virtual bool constrainsEvents() const { return false; }
  /// \brief Back to the start of a run (keeps what was learned: network, memory).
  virtual void reset() {}
  /// \brief Every sample before the command: what happened. Default: the paper's attention
  /// function on (e, e_dot) (eq. attention).
  virtual Detection detect(const Sample& s, const Vec& theta_hat, Attention* attention);
  /// \brief At an onset: may reset theta_hat; fills the event's reset field.
  virtual void onOnset(const Sample& s, Vec* theta_hat, Event* ev) = 0;
  /// \brief At a kDecision detection: may move theta_hat; fills the event.
  virtual void onDecision(const Sample& s, Vec* theta_hat, Event* ev);
  /// \brief Every sample of an active phase, after the command u [rad] was computed.
  virtual void duringPhase(const Sample& s, double u, const Vec& theta_hat) = 0;
  /// \brief At a recovery: learn from the phase; fills cost, grad, learned.
  virtual void onRecovery(const Sample& s, const Vec& theta_hat, Event* ev) = 0;
  /// \brief Every sample after the adaptation law: an identifier may refine theta_hat here
  /// (concurrent learning). Returns true when it changed theta_hat (the controller then
  /// projects it onto Omega when projection is on).
  virtual bool refine(Vec* theta_hat) {
    (void)theta_hat;
    return false;
  }
  /// \brief E = integral |e| dt of the current phase [rad s].
  virtual double phaseCost() const { return 0.0; }
  /// \brief dE/dtheta_hat_I of the current phase (learning modes; empty otherwise).
  virtual const Vec* phaseGradient() const { return nullptr; }
  /// \brief New tunables (Controller::setTunables) between two samples; `cfg` the controller's
  /// parameters and `robust` pa_robust's, with them. Returns true when the strategy had to restart
  /// its detection (the controller then ends an open phase).
  virtual bool setTunables(const ControllerParams& cfg, const RobustParams& robust) {
    (void)cfg;
    (void)robust;
    return false;
  }
  /// \brief An excitation [rad] the controller adds to the command at sample time t (an
  /// identifier's probing signal; 0: none, the paper's modes).
  virtual double excitation(double t) const {
    (void)t;
    return 0.0;
  }
  /// \brief Whether the strategy has an error feedback (only pa_robust; the paper's modes have
  /// none and are unchanged).
  virtual bool hasErrorFeedback() const { return false; }
  /// \brief The error feedback's command k s at time t for s = e^T P B, subtracted from the
  /// adaptive term; called once a sample.
  virtual double errorFeedback(double t, double s) {
    (void)t;
    (void)s;
    return 0.0;
  }
  /// \brief Start a phase with theta_hat already set (an external trigger, Controller::startPhase).
  virtual void startExternalPhase() {}
};

}  // namespace preadaptive_mrac
