#include "preadaptive_mrac/core/controller.hpp"

#include <cmath>
#include <stdexcept>

#include "preadaptive_mrac/core/oracle_preadaptation.hpp"
#include "preadaptive_mrac/core/paper_preadaptation.hpp"
#include "preadaptive_mrac/core/params.hpp"
#include "preadaptive_mrac/core/plant.hpp"
#include "preadaptive_mrac/core/robust_preadaptation.hpp"
#include "preadaptive_mrac/core/small_ops.hpp"
#include "preadaptive_mrac/core/tunables.hpp"

namespace preadaptive_mrac {

Controller::Controller(const PlantConfig& plant, const ControllerConfig& cfg)
    : Controller(plant, cfg, designController(plant.A, plant.B, cfg.Q, cfg.R)) {}

Controller::Controller(const PlantConfig& plant, const ControllerConfig& cfg,
                       const ControllerDesign& design)
    : cfg_(cfg),
      design_(design),
      n_(plant.n()),
      out_(plant.output_index),
      dt_(cfg.sample_time),
      vel_(cfg.tau, cfg.sample_time),
      attention_(cfg.c_e, cfg.c_ed, cfg.confirm_samples, cfg.hysteresis),
      net_(cfg.hidden, plant.n(), cfg.seed, cfg.init_scale) {
  K_ = design_.K.transpose();
  B_ = plant.B;
  PB_ = design_.P * plant.B;
  b_ref_ = plant.B1r + cfg.k0 * plant.B;
  const Eigen::MatrixXd M = design_.Ar * dt_;
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n_, n_);
  const Eigen::MatrixXd M2 = M * M, M3 = M2 * M, M4 = M3 * M;
  // Classic RK4 applied to x_r' = A_r x_r + b r with r held: exactly these polynomials.
  Phi_r_ = I + M + M2 / 2.0 + M3 / 6.0 + M4 / 24.0;
  Gam_r_ = dt_ * (I + M / 2.0 + M2 / 6.0 + M3 / 24.0) * b_ref_;
  x0_ = plant.x0;
  ev_.setZero(n_);
  upd_.setZero(n_);
  limits_ = plant.actuator;
  switch (cfg.mode) {
    case Mode::kPaRobust:
      strategy_ = std::make_unique<RobustPreadaptation>(cfg, plant, &net_);
      break;
    case Mode::kOracle:
      strategy_ = std::make_unique<OraclePreadaptation>(cfg.sample_time);
      break;
    case Mode::kL1:  // attention evaluated and reported as in rac, theta_hat never reset
      strategy_ =
          std::make_unique<PaperPreadaptation>(Mode::kRac, cfg, design_, B_, PB_, out_, &net_);
      l1_ = L1Law(design_, B_, b_ref_, cfg.k0, cfg.l1, dt_, cfg.theta_hat0, plant.x0);
      break;
    default:
      strategy_ =
          std::make_unique<PaperPreadaptation>(cfg.mode, cfg, design_, B_, PB_, out_, &net_);
  }
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
  theta_hat_ = o.theta_hat_;
  ev_ = o.ev_;
  upd_ = o.upd_;
  limits_ = o.limits_;
  u_prev_ = o.u_prev_;
  u_cmd_prev_ = o.u_cmd_prev_;
  r_prev_ = o.r_prev_;
  vel_ = o.vel_;
  attention_ = o.attention_;
  net_ = o.net_;
  strategy_ = o.strategy_->clone(&net_);
  l1_ = o.l1_;
  pending_ = o.pending_;
  return *this;
}

void Controller::reset() {
  x_r_ = x0_;
  theta_hat_ = cfg_.theta_hat0;
  vel_.reset();
  attention_.reset();
  strategy_->reset();
  if (cfg_.mode == Mode::kL1) {
    l1_.reset();
    theta_hat_ = l1_.thetaHat();
  }
  u_prev_ = 0.0;
  u_cmd_prev_ = 0.0;
  r_prev_ = 0.0;
}

Vec Controller::phaseGradient() const {
  const Vec* g = strategy_->phaseGradient();
  return g != nullptr ? *g : Vec(Vec::Zero(n_));
}

void Controller::project(const Vec& theta, Vec* y) const {
  // f(theta) = ((1 + eps) |theta|^2 - theta_max^2) / (eps theta_max^2): f <= 0 inside the inner
  // ball, f = 1 on |theta| = theta_max. Outward components of y are scaled down by f there.
  const double tm2 = cfg_.theta_max * cfg_.theta_max;
  const double eps = cfg_.projection_epsilon;
  const double f = ((1.0 + eps) * theta.squaredNorm() - tm2) / (eps * tm2);
  if (f <= 0.0) return;
  const double grad_dot_y = theta.dot(*y);  // grad f is parallel to theta
  if (grad_dot_y <= 0.0) return;
  const double th2 = theta.squaredNorm();
  *y -= (std::min(f, 1.0) * grad_dot_y / th2) * theta;
}

void Controller::setNetwork(const NetworkState& s) {
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
  theta_hat_ = theta_I;
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
  if (strategy_->setTunables(cfg_)) attention_.endPhase();
  // Projection switched on: the estimate starts inside Omega, as at a reset.
  if (cfg_.projection) clampToBall(&theta_hat_, cfg_.theta_max);
}

StepOutput Controller::step(const StepInput& in) {
  const Vec& x = *in.x;
  if (strategy_->needsTruth() && in.theta_true == nullptr)
    throw std::invalid_argument(std::string("mode ") + modeName(cfg_.mode) +
                                " needs the true theta at every step");

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
  smp.u_prev = in.u_applied != nullptr ? *in.u_applied : u_cmd_prev_;
  smp.r_prev = r_prev_;
  const Detection det = strategy_->detect(smp, theta_hat_, &attention_);
  if (det != Detection::kNone) {
    Event ev;
    ev.t = in.t;
    ev.e = out.e;
    ev.e_dot = out.e_dot;
    ev.theta_hat_before = theta_hat_;
    switch (det) {
      case Detection::kOnset:
        ev.type = Event::Type::kOnset;
        attention_.forceActive();
        strategy_->onOnset(smp, &theta_hat_, &ev);
        break;
      case Detection::kRecovered:
        ev.type = Event::Type::kRecovered;
        attention_.endPhase();
        strategy_->onRecovery(smp, theta_hat_, &ev);
        break;
      case Detection::kIgnoredOnset:
        ev.type = Event::Type::kIgnoredOnset;
        break;
      case Detection::kIgnoredRecovery:
        ev.type = Event::Type::kIgnoredRecovery;
        break;
      case Detection::kDecision:
        ev.type = Event::Type::kDecision;
        strategy_->onDecision(smp, &theta_hat_, &ev);
        break;
      case Detection::kNone:
        break;
    }
    // A reset by pa_robust or the oracle stays in Omega when projection is on (the paper's
    // modes reset as the paper does, unprojected: they are the reproduction).
    if (cfg_.projection && (cfg_.mode == Mode::kPaRobust || cfg_.mode == Mode::kOracle))
      clampToBall(&theta_hat_, cfg_.theta_max);
    ev.theta_hat_after = theta_hat_;
    ev.episodes = net_.state().episodes;
    out.event = ev;
  }

  out.u_baseline = -dotOf(K_, x);
  const bool l1 = cfg_.mode == Mode::kL1;
  out.u_adaptive = l1 ? l1_.command(x, in.r) : -dotOf(theta_hat_, x) + cfg_.k0 * in.r;
  out.u_unsaturated = out.u_baseline + out.u_adaptive;
  // The command the actuator can follow; the plant applies the same limits.
  out.u = limits_.apply(out.u_unsaturated, u_prev_, dt_);
  out.saturated = out.u != out.u_unsaturated;
  u_prev_ = out.u;
  u_cmd_prev_ = out.u;
  copyTo(x_r_, &out.x_ref);
  copyTo(theta_hat_, &out.theta_hat);

  if (attention_.phaseActive()) strategy_->duringPhase(smp, out.u, theta_hat_);
  if (l1) {  // the L1 law adapts from its predictor; the plant got u - u_bl of the command
    l1_.advance(x, in.r, out.u - out.u_baseline, !(out.saturated && cfg_.freeze_when_saturated));
    copyTo(l1_.thetaHat(), &theta_hat_);
  } else if (!(out.saturated && cfg_.freeze_when_saturated)) {
    // Adaptation law (eq. adaptivecontrol), forward Euler with the sampled x; frozen while the
    // elevator is limited (the plant does not get the u the law assumes), projected onto Omega.
    scaledTo(cfg_.gamma * dotOf(ev_, PB_), x, &upd_);
    if (cfg_.projection) {
      project(theta_hat_, &upd_);
      addScaled(dt_, upd_, &theta_hat_);
      clampToBall(&theta_hat_,
                  cfg_.theta_max);  // the Euler step can overshoot the boundary layer by O(dt)
    } else {
      addScaled(dt_, upd_, &theta_hat_);
    }
  }
  if (strategy_->refine(&theta_hat_) && cfg_.projection) clampToBall(&theta_hat_, cfg_.theta_max);
  // Reference model (eq. refmodel), RK4 with r held over the sample.
  lazyProductPlus(Phi_r_, x_r_, Gam_r_, in.r, &x_r_);
  r_prev_ = in.r;
  return out;
}

}  // namespace preadaptive_mrac
