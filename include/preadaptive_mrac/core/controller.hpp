#pragma once
/// \file controller.hpp
/// \brief LQR baseline + MRAC with attention and preadaptation: the controller of Fig. 1.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "preadaptive_mrac/core/input_guard.hpp"
#include "preadaptive_mrac/core/l1_law.hpp"
#include "preadaptive_mrac/core/network.hpp"
#include "preadaptive_mrac/core/plant.hpp"
#include "preadaptive_mrac/core/preadaptation.hpp"
#include "preadaptive_mrac/core/solvers.hpp"
#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

class ParamReader;

/// \brief What the preadaptation does at an onset and after a phase.
enum class Mode {
  kRac,           ///< regular adaptive control: never resets theta_hat
  kPa,            ///< preadaptation, network fixed
  kPaLearn,       ///< preadaptation, learning with the approximate gradient (Pi_hat)
  kPaLearnExact,  ///< preadaptation, learning with the exact gradient (needs true theta)
  kPaRobust,      ///< robust preadaptation: residual trigger, regime memory, verification
  kOracle,        ///< yardstick: theta_hat := true theta at each switch (needs true theta)
  kL1,            ///< L1 adaptive control (docs/l1.md) in place of the MRAC law; never resets
};
const char* modeName(Mode m);
/// \brief Parse "rac" | "pa" | "pa_learn" | "pa_learn_exact" | "pa_robust" | "oracle" | "l1".
std::optional<Mode> parseMode(const std::string& s);

/// \brief Parameters of pa_robust (key `controller.robust`; docs/robust.md).
struct RobustConfig {
  double detect_window = 0.02;    ///< window of the identification residual [s]
  double chunk = 0.005;           ///< data chunk of the verification scores [s]
  double long_window = 0.2;       ///< second, longer residual window (0 = off) [s]
  double threshold = 0.005;       ///< smallest mean residual that triggers [rad]
  double noise_factor = 5.0;      ///< trigger also needs residual > factor x its noise level
  double noise_time = 2.0;        ///< horizon of the noise-level estimate [s]
  double verify_time = 0.05;      ///< decisions are re-made on growing data for this long [s]
  double margin = 0.2;            ///< a candidate must score this fraction below keeping
  double significance = 9.0;      ///< improvements must exceed this many noise variances
  double prior_std = 1.0;         ///< prior spread of theta around the chosen candidate
  double ridge = 1e-2;            ///< floor of the fit's ridge, relative to the data's energy
  double cl_gain = 2.0;           ///< concurrent learning: pull towards the regime's fit [1/s]
  int memory_size = 8;            ///< regimes remembered (least used dropped first)
  double merge_tolerance = 0.02;  ///< regimes closer than this on the visited states merge [rad]
  double settle_time = 1.0;       ///< a regime is banked only after lasting this long [s]
  double quiet_time = 1.0;        ///< phase ends after the residual is quiet this long [s]
  bool use_network = true;        ///< the network's prediction is one of the candidates
  double network_rate = 0.05;     ///< its supervised learning rate at each recovery

  static RobustConfig read(ParamReader& r, const std::string& prefix);
  void validate(ParamReader& r, const std::string& prefix) const;
};

/// \brief Controller parameters (key `controller`); see config/controller/default.yaml.
struct ControllerConfig {
  Mode mode = Mode::kPaLearn;
  double sample_time = 0.001;         ///< controller period dt [s]
  Eigen::MatrixXd Q;                  ///< LQR state weight (n x n, symmetric >= 0)
  double R = 1.0;                     ///< LQR input weight (> 0)
  double k0 = 0.0;                    ///< feed-forward gain of r (B2r = k0 B)
  double gamma = 10.0;                ///< adaptation gain
  Eigen::VectorXd theta_hat0;         ///< initial estimate (n)
  double tau = 0.01;                  ///< velocity-estimator time constant [s]
  double c_e = 0.005;                 ///< attention error threshold [rad]
  double c_ed = 0.02;                 ///< attention rate threshold [rad/s]
  int hidden = 3;                     ///< hidden neurons
  double init_scale = 1.0;            ///< initial weights uniform in [-init_scale, init_scale]
  std::uint64_t seed = 1;             ///< seed of the initial weights
  double gamma_pa = 10.0;             ///< learning rate of the preadaptation learner
  int confirm_samples = 0;            ///< attention debounce: crossings must hold this many samples
  double hysteresis = 0.0;            ///< attention: recovery threshold is c_e - hysteresis [rad]
  bool freeze_when_saturated = true;  ///< no adaptation while the elevator is at a limit
  bool projection = false;          ///< smooth projection of theta_hat onto ||theta|| <= theta_max
  double theta_max = 0.0;           ///< radius of Omega
  double projection_epsilon = 0.1;  ///< width of the projection's boundary layer (> 0)
  RobustConfig robust;              ///< pa_robust (optional section; defaults documented)
  L1Config l1;                      ///< mode l1 (optional section `controller.l1`; docs/l1.md)

  /// \brief Read the `controller` section for a plant of n states; problems go to the reader.
  static ControllerConfig read(ParamReader& r, int n, const std::string& prefix = "controller");
  /// \brief Every problem with the values (signs, sizes, finiteness) into the reader.
  void validate(ParamReader& r, int n, const std::string& prefix = "controller") const;
};

/// \brief The parameters that may change while the controller runs (dynamic_reconfigure):
/// attention thresholds, adaptation and learning gains, projection and pa_robust's parameters.
/// Controller::setTunables queues them; they take effect at the start of the next step().
struct ControllerTunables {
  double c_e = 0.005;               ///< controller.attention.c_e [rad]
  double c_ed = 0.02;               ///< controller.attention.c_ed [rad/s]
  int confirm_samples = 0;          ///< controller.attention.confirm_samples
  double hysteresis = 0.0;          ///< controller.attention.hysteresis [rad]
  double gamma = 10.0;              ///< controller.adaptation.gamma
  double gamma_pa = 10.0;           ///< controller.preadaptation.gamma_pa
  bool projection = false;          ///< controller.projection.enabled
  double theta_max = 0.0;           ///< controller.projection.theta_max
  double projection_epsilon = 0.1;  ///< controller.projection.epsilon
  RobustConfig robust;              ///< controller.robust.*

  /// \brief The tunables of a configuration.
  static ControllerTunables of(const ControllerConfig& c);
  /// \brief Write these values into a configuration.
  void applyTo(ControllerConfig* c) const;
};

/// \brief An attention event.
struct Event {
  enum class Type { kOnset, kRecovered, kIgnoredOnset, kIgnoredRecovery, kDecision };
  /// \brief What a verification (pa_robust) chose.
  enum class Decision { kNone, kKeep, kFit, kMemory, kNetwork };
  Type type = Type::kOnset;
  double t = 0.0;             ///< sample time [s]
  double e = 0.0;             ///< output error alpha - alpha_r [rad]
  double e_dot = 0.0;         ///< estimated rate of e [rad/s]
  Vec theta_hat_before;       ///< estimate before the event
  Vec theta_hat_after;        ///< estimate after (the reset value on onsets in pa modes)
  bool reset = false;         ///< theta_hat was reset to theta_hat_I
  double cost = 0.0;          ///< E = integral |e| dt over the phase (recoveries)
  Vec grad;                   ///< dE/dtheta_hat_I (recoveries in learning modes)
  bool learned = false;       ///< the network was updated
  std::int64_t episodes = 0;  ///< learning episodes after the event
  // pa_robust verification (onsets and decisions):
  Decision decision = Decision::kNone;  ///< keep, fit the data, a remembered regime, network
  int chosen = -1;                      ///< index of the remembered regime chosen (kMemory)
  int candidates = 0;                   ///< candidates scored (keep, memory, network)
  double score = 0.0;       ///< RMS identification residual of the estimate kept or set [rad]
  double score_keep = 0.0;  ///< the same for keeping the pre-switch estimate [rad]
};
const char* eventTypeName(Event::Type t);
const char* decisionName(Event::Decision d);

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

/// \brief Attention function (eq. attention) with the phase state of SPEC.md.
///
/// Two options against noise, both off by default (the paper's behaviour): `confirm_samples`
/// N > 0 accepts a crossing only when |e| stays on the new side for N more samples, and checks
/// the rate condition at the confirming sample; `hysteresis` h > 0 puts the recovery
/// threshold at c_e - h.
class Attention {
 public:
  enum class Result { kNone, kOnset, kRecovered, kIgnoredOnset, kIgnoredRecovery };
  Attention(double c_e, double c_ed, int confirm_samples = 0, double hysteresis = 0.0)
      : c_e_(c_e), c_ed_(c_ed), confirm_(confirm_samples), hyst_(hysteresis) {}
  /// \brief New thresholds between two samples. The last sample is re-evaluated against them,
  /// so the change itself is no crossing; a changed confirm_samples drops pending crossings.
  void setThresholds(double c_e, double c_ed, int confirm_samples, double hysteresis);
  /// \brief Evaluate one sample of e and its estimated rate.
  Result update(double e, double e_dot);
  bool phaseActive() const { return active_; }
  /// \brief Enter a phase without an onset (an externally triggered phase).
  void forceActive() { active_ = true; }
  /// \brief Leave the phase (a strategy's own recovery).
  void endPhase() { active_ = false; }
  void reset() {
    primed_ = false;
    active_ = false;
    up_count_ = down_count_ = -1;
  }

 private:
  Result decideUp(double e_dot);
  Result decideDown(double e_dot);
  double c_e_, c_ed_;
  int confirm_;
  double hyst_;
  bool primed_ = false, active_ = false;
  double s_prev_ = 0.0, d_prev_ = 0.0;   // |e| - c_e and |e| - (c_e - h) at the last sample
  double abs_e_prev_ = 0.0;              // |e| at the last sample (setThresholds)
  int up_count_ = -1, down_count_ = -1;  // samples held since a crossing; -1 when none pending
};

/// \brief Sensitivity of the phase cost to theta_hat_I (eqs. E-der-exp, dot-ev-hth-der-exp),
/// S_dot = Pi S integrated alongside the controller.
class SensitivityTracker {
 public:
  SensitivityTracker() = default;
  SensitivityTracker(const Mat& Ar, const Vec& B, const Vec& PB, double gamma, int out);
  /// \brief Start a phase: S = [0; I], E = 0, g = 0.
  void start();
  /// \brief Add one sample's contribution over [t, t+dt): E += |e| dt, g += sign(e) S[out,:] dt,
  /// then S += dt Pi S. `theta_err` = theta - theta_hat (zero for the approximate gradient).
  void accumulate(double dt, const Vec& ev, const Vec& x, const Vec& theta_err);
  /// \brief Pi (2n x 2n) at the given signals; for tests and documentation, not the hot path.
  PiMat pi(const Vec& ev, const Vec& x, const Vec& theta_err) const;
  /// \brief A new adaptation gain from the next sample on (Controller::setTunables).
  void setGamma(double gamma) { gamma_ = gamma; }
  double cost() const { return E_; }
  const Vec& grad() const { return g_; }
  const SensMat& S() const { return S_; }

 private:
  Mat Ar_;
  Vec B_, PB_;
  double gamma_ = 0.0;
  int out_ = 1, n_ = 0;
  SensMat S_, Sdot_;
  double E_ = 0.0;
  Vec g_;
  /// \brief The rest of accumulate() for n = 3 (after E), without run-time sizes.
  void accumulate3(double dt, double sgn, const Vec& ev, const Vec& x, const Vec& theta_err);
};

/// \brief The whole controller: one step per sample, as in Fig. 1 of the paper.
///
/// Per sample t_k with measured x_k: e_v = x_k - x_r; velocity estimate; attention (onset
/// resets theta_hat to the network's theta_hat_I in pa modes; recovery updates the network in
/// learning modes); u = -K x - theta_hat^T x + k0 r; then x_r, theta_hat (Euler, eq.
/// adaptivecontrol) and the sensitivity advance to t_k + dt.
class Controller {
 public:
  /// \brief Derives K (CARE) and P (Lyapunov) from the plant's A, B and the config's Q, R;
  /// throws SolverError when that is impossible. The plant is known only through A, B, B1r.
  Controller(const PlantConfig& plant, const ControllerConfig& cfg);
  /// \brief The same with K and P already solved: `design` must be designController() of
  /// plant.A, plant.B, cfg.Q and cfg.R (RunConfig::design).
  Controller(const PlantConfig& plant, const ControllerConfig& cfg, const ControllerDesign& design);
  /// \brief A snapshot: the copy has its own network and strategy state.
  Controller(const Controller& other);
  Controller& operator=(const Controller& other);

  /// \brief One sample. Allocation-free.
  StepOutput step(const StepInput& in);
  /// \brief Back to the initial state (x_r, theta_hat, estimator, attention); keeps the network.
  void reset();

  const ControllerDesign& design() const { return design_; }
  const ControllerConfig& config() const { return cfg_; }
  Mode mode() const { return cfg_.mode; }
  const Vec& thetaHat() const { return theta_hat_; }
  const Vec& xRef() const { return x_r_; }
  bool phaseActive() const { return attention_.phaseActive(); }
  const PreadaptNetwork& network() const { return net_; }
  /// \brief Replace the network (e.g. loaded weights); sizes must match hidden x n.
  void setNetwork(const NetworkState& s);
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

 private:
  ControllerConfig cfg_;
  ControllerDesign design_;
  int n_, out_;
  double dt_;
  Vec K_, B_, PB_, b_ref_;
  Mat Phi_r_;  // RK4 transition of the reference model over dt
  Vec Gam_r_;  // RK4 input vector of the reference model over dt (times r)
  /// \brief Smooth projection (Pomet-Praly) of the update direction y at theta.
  void project(const Vec& theta, Vec* y) const;

  Vec x0_, x_r_, theta_hat_, ev_, upd_;
  ActuatorLimits limits_;
  double u_prev_ = 0.0;      // last command sent (the rate limiter's memory; safeCommand too)
  double u_cmd_prev_ = 0.0;  // last answer of step() (what the plant applies in lockstep)
  double r_prev_ = 0.0;
  VelocityEstimator vel_;
  Attention attention_;
  PreadaptNetwork net_;
  std::unique_ptr<PreadaptationStrategy> strategy_;
  L1Law l1_;  // mode l1: the adaptive term and theta_hat come from the L1 law
  std::optional<ControllerTunables> pending_;  // queued by setTunables, applied by step()
  void applyTunables(const ControllerTunables& t);
};

}  // namespace preadaptive_mrac
