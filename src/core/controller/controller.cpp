#include "preadaptive_mrac/core/controller/controller.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "preadaptive_mrac/core/controller/mode_registry.hpp"
#include "preadaptive_mrac/core/controller/tunables.hpp"
#include "preadaptive_mrac/core/robust/regime_memory.hpp"
#include "preadaptive_mrac/core/schema/params.hpp"
#include "preadaptive_mrac/core/small_ops.hpp"

namespace preadaptive_mrac {

// The controller knows the plant only through its design model: the LQR, the reference model
// and every law and strategy below are built on `model`.
Controller::Controller(const DesignModel& model, const ControllerConfig& cfg)
    : Controller(model, cfg, designOf(model, cfg)) {}

ControllerDesign Controller::designOf(const DesignModel& model, const ControllerConfig& cfg) {
  return designController(model.A, model.B, cfg.Q, cfg.R);
}

Controller::Controller(const DesignModel& model, const ControllerConfig& cfg,
                       const ControllerDesign& design)
    : cfg_(cfg),
      design_(design),
      n_(model.n()),
      out_(model.output_index),
      dt_(cfg.sample_time),
      vel_(cfg.tau, cfg.sample_time),
      attention_(cfg.c_e, cfg.c_ed, cfg.confirm_samples, cfg.hysteresis),
      net_(cfg.hidden, model.n(), cfg.seed, cfg.init_scale) {
  K_ = design_.K.transpose();
  B_ = model.B;
  PB_ = design_.P * model.B;
  b_ref_ = model.B1r + cfg.k0 * model.B;
  // The reference model x_r' = A_r x_r + b r, RK4 with r held over the sample.
  const Rk4Hold hold = rk4Hold(design_.Ar, dt_);
  Phi_r_ = hold.Phi;
  Gam_r_ = hold.G * b_ref_;
  x0_ = model.x0;
  ev_.setZero(n_);
  // Hedging needs limits the controller knows; without them nothing is ever limited.
  hedge_ = cfg.hedging == Hedging::kPch && model.limits.enabled;
  Gam_b_ = hold.G * B_;
  ev_h_.setZero(n_);
  limits_ = model.limits;
  const ModeEntry* mode = findMode(cfg.mode);
  if (mode == nullptr)
    throw std::invalid_argument("controller.mode: expected one of " + modeNames(", ") + ", got '" +
                                cfg.mode + "'");
  ModeContext ctx;
  ctx.cfg = &cfg_;
  ctx.l1 = &cfg_.l1;
  ctx.robust = &cfg_.robust;
  ctx.model = &model;  // the factories copy what they keep
  ctx.design = &design_;
  ctx.B = &B_;
  ctx.PB = &PB_;
  ctx.net = &net_;
  law_ = mode->make_law(ctx);
  mrac_ = dynamic_cast<MracLaw*>(law_.get());
  strategy_ = mode->make_strategy(ctx);
  reset();
}

Controller::Controller(const Controller& other) : vel_(other.vel_), attention_(other.attention_) {
  *this = other;
}

Controller& Controller::operator=(const Controller& o) {
  if (this == &o) return *this;
  cfg_ = o.cfg_;
  design_ = o.design_;
  n_ = o.n_;
  out_ = o.out_;
  dt_ = o.dt_;
  K_ = o.K_;
  B_ = o.B_;
  PB_ = o.PB_;
  b_ref_ = o.b_ref_;
  Phi_r_ = o.Phi_r_;
  Gam_r_ = o.Gam_r_;
  x0_ = o.x0_;
  x_r_ = o.x_r_;
  ev_ = o.ev_;
  hedge_ = o.hedge_;
  Gam_b_ = o.Gam_b_;
  x_h_ = o.x_h_;
  ev_h_ = o.ev_h_;
  limits_ = o.limits_;
  u_prev_ = o.u_prev_;
  u_cmd_prev_ = o.u_cmd_prev_;
  r_prev_ = o.r_prev_;
  vel_ = o.vel_;
  attention_ = o.attention_;
  net_ = o.net_;
  law_ = o.law_->clone();
  mrac_ = dynamic_cast<MracLaw*>(law_.get());
  strategy_ = o.strategy_->clone(&net_);
  pending_ = o.pending_;
  return *this;
}

void Controller::reset() {
  x_r_ = x0_;
  x_h_ = x0_;
  law_->reset();
  vel_.reset();
  attention_.reset();
  strategy_->reset();
  u_prev_ = 0.0;
  u_cmd_prev_ = 0.0;
  r_prev_ = 0.0;
}

Vec Controller::phaseGradient() const {
  const Vec* g = strategy_->phaseGradient();
  return g != nullptr ? *g : Vec(Vec::Zero(n_));
}

void Controller::setNetwork(const LearnedState& s) {
  if (s.hidden() != cfg_.hidden || s.outputs() != n_)
    throw std::invalid_argument("network has " + std::to_string(s.hidden()) + " hidden x " +
                                std::to_string(s.outputs()) + " outputs, the controller needs " +
                                std::to_string(cfg_.hidden) + " x " + std::to_string(n_));
  net_ = PreadaptNetwork(s);
  RegimeMemory(&net_.state().regimes, cfg_.robust.memory_size).trim();
  // The assignment gave the memory the loaded file's capacity: reserve the bound again, so
  // remembering a regime during the run never allocates.
  net_.state().regimes.reserve(static_cast<size_t>(std::max(cfg_.robust.memory_size, 0)) + 1);
}

double Controller::safeCommand(const Vec& x_last, StalePolicy policy) {
  const double u = policy == StalePolicy::kZero ? 0.0 : -K_.dot(x_last);
  u_prev_ = limits_.apply(u, u_prev_, dt_);
  return u_prev_;
}

void Controller::startPhase(const Vec& theta_I) {
  if (theta_I.size() != n_)
    throw std::invalid_argument("startPhase: theta_I must have " + std::to_string(n_) + " entries");
  *law_->mutableEstimate() = theta_I;
  attention_.forceActive();
  strategy_->startExternalPhase();
}

void Controller::setTunables(const ControllerTunables& t) {
  const std::vector<std::string> problems = validateTunables(cfg_, t);
  if (!problems.empty()) throw ConfigError(problems);
  pending_ = t;
}

void Controller::applyTunables(const ControllerTunables& t) {
  t.applyTo(&cfg_);
  attention_.setThresholds(cfg_.c_e, cfg_.c_ed, cfg_.confirm_samples, cfg_.hysteresis);
  if (strategy_->setTunables(cfg_, cfg_.robust)) attention_.endPhase();
  law_->setTunables(cfg_);
}

StepOutput Controller::step(const StepInput& in) {
  const Vec& x = *in.x;
  if (strategy_->needsTruth() && in.theta_true == nullptr)
    throw std::invalid_argument("mode " + cfg_.mode + " needs the true theta at every step");

  StepOutput out;
  if (pending_) {  // a step boundary: queued tunables take effect before this sample
    applyTunables(*pending_);
    pending_.reset();
    out.tunables_applied = true;
  }
  differenceTo(x, x_r_, &ev_);
  out.e = ev_[out_];
  out.e_dot = vel_.update(out.e);

  Sample smp;
  smp.t = in.t;
  smp.x = in.x;
  smp.r = in.r;
  smp.theta_true = in.theta_true;
  smp.ev = &ev_;
  smp.e = out.e;
  smp.e_dot = out.e_dot;
  // The surface position when the plant reports it and the configuration takes it; else the
  // controller's own last command (then a delay or lag is model error to the identification).
  smp.u_prev = in.u_applied != nullptr && cfg_.elevator_feedback == ElevatorFeedback::kMeasured
                   ? *in.u_applied
                   : u_cmd_prev_;
  smp.r_prev = r_prev_;
  // The law's estimate: strategies read and reset it here, the law advances it below.
  Vec& theta_hat = *law_->mutableEstimate();
  const Detection det = strategy_->detect(smp, theta_hat, &attention_);
  if (det != Detection::kNone) {
    Event ev;
    ev.t = in.t;
    ev.e = out.e;
    ev.e_dot = out.e_dot;
    ev.theta_hat_before = theta_hat;
    switch (det) {
      case Detection::kOnset:
        ev.type = Event::Type::kOnset;
        attention_.forceActive();
        strategy_->onOnset(smp, &theta_hat, &ev);
        break;
      case Detection::kRecovered:
        ev.type = Event::Type::kRecovered;
        attention_.endPhase();
        strategy_->onRecovery(smp, theta_hat, &ev);
        break;
      case Detection::kIgnoredOnset:
        ev.type = Event::Type::kIgnoredOnset;
        break;
      case Detection::kIgnoredRecovery:
        ev.type = Event::Type::kIgnoredRecovery;
        break;
      case Detection::kDecision:
        ev.type = Event::Type::kDecision;
        strategy_->onDecision(smp, &theta_hat, &ev);
        break;
      case Detection::kNone:
        break;
    }
    // A reset by pa_robust or the oracle stays in Omega when projection is on (the paper's
    // modes reset as the paper does, unprojected: they are the reproduction).
    if (strategy_->constrainsEvents()) law_->constrain();
    ev.theta_hat_after = theta_hat;
    ev.episodes = net_.state().episodes;
    out.event = ev;
  }

  LawInput li;
  li.x = in.x;
  li.ev = &ev_;
  li.r = in.r;
  if (hedge_) {
    differenceTo(x, x_h_, &ev_h_);
    li.ev = &ev_h_;
  }
  out.u_baseline = -dotOf(K_, x);
  out.u_adaptive = lawCommand(li);
  // A strategy's probing signal is part of the adaptive term (only pa_robust has one).
  const double excitation = strategy_->excitation(in.t);
  if (excitation != 0.0) out.u_adaptive += excitation;
  // A strategy's error feedback: -k e^T P B makes V = e^T P e fall faster than the estimate
  // alone makes it (e_dot = A_r e + B (theta - theta_hat)^T x + B u_ef), so the error a switch
  // left returns sooner. On the error against the reference model itself, hedged or not: a
  // proportional term holds no state to wind up, and the rate limit's share of a transient is
  // error it should act on.
  if (strategy_->hasErrorFeedback())
    out.u_adaptive -= strategy_->errorFeedback(in.t, dotOf(ev_, PB_));
  out.u_unsaturated = out.u_baseline + out.u_adaptive;
  // The command the actuator can follow; the plant applies the same limits.
  out.u = limits_.apply(out.u_unsaturated, u_prev_, dt_);
  out.saturated = out.u != out.u_unsaturated;
  u_prev_ = out.u;
  u_cmd_prev_ = out.u;
  copyTo(x_r_, &out.x_ref);
  copyTo(theta_hat, &out.theta_hat);

  if (attention_.phaseActive()) strategy_->duringPhase(smp, out.u, theta_hat);
  // The adaptive law to t_{k+1}. Hedged, it adapts through the limit: its error and prediction
  // carry what the limit took off. Unhedged, it is frozen while the elevator is limited (the
  // plant does not get the u the law assumes).
  if (hedge_) {
    // The hedge is at most the elevator's travel: a command beyond the aircraft's authority
    // (an unstable plant past recovery) would otherwise drive the hedged model, the error and
    // the estimate without bound; past it the law freezes, as unhedged.
    const double travel = limits_.max_deflection;
    const double deficit = out.u - out.u_unsaturated;
    li.limited = std::max(-travel, std::min(travel, deficit));
    lawAdvance(li, std::abs(deficit) <= travel);
    // The hedged reference model, RK4 with r and the limited part held over the sample.
    lazyProductPlus(Phi_r_, x_h_, Gam_r_, in.r, &x_h_);
    addScaled(li.limited, Gam_b_, &x_h_);
  } else {
    lawAdvance(li, !(out.saturated && cfg_.freeze_when_saturated));
  }
  if (strategy_->refine(&theta_hat)) law_->constrain();
  // Reference model (eq. refmodel), RK4 with r held over the sample.
  lazyProductPlus(Phi_r_, x_r_, Gam_r_, in.r, &x_r_);
  r_prev_ = in.r;
  return out;
}

}  // namespace preadaptive_mrac
