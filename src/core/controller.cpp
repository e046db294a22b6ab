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

const char* modeName(Mode m) {
  switch (m) {
    case Mode::kRac:
      return "rac";
    case Mode::kPa:
      return "pa";
    case Mode::kPaLearn:
      return "pa_learn";
    case Mode::kPaLearnExact:
      return "pa_learn_exact";
    case Mode::kPaRobust:
      return "pa_robust";
    case Mode::kOracle:
      return "oracle";
    case Mode::kL1:
      return "l1";
  }
  return "?";
}

std::optional<Mode> parseMode(const std::string& s) {
  if (s == "rac") return Mode::kRac;
  if (s == "pa") return Mode::kPa;
  if (s == "pa_learn") return Mode::kPaLearn;
  if (s == "pa_learn_exact") return Mode::kPaLearnExact;
  if (s == "pa_robust") return Mode::kPaRobust;
  if (s == "oracle") return Mode::kOracle;
  if (s == "l1") return Mode::kL1;
  return std::nullopt;
}

const char* eventTypeName(Event::Type t) {
  switch (t) {
    case Event::Type::kOnset:
      return "onset";
    case Event::Type::kRecovered:
      return "recovered";
    case Event::Type::kIgnoredOnset:
      return "ignored_onset";
    case Event::Type::kIgnoredRecovery:
      return "ignored_recovery";
    case Event::Type::kDecision:
      return "decision";
  }
  return "?";
}

const char* decisionName(Event::Decision d) {
  switch (d) {
    case Event::Decision::kNone:
      return "none";
    case Event::Decision::kKeep:
      return "keep";
    case Event::Decision::kFit:
      return "fit";
    case Event::Decision::kMemory:
      return "memory";
    case Event::Decision::kNetwork:
      return "network";
  }
  return "?";
}

namespace {
// The real-valued keys of controller.robust with their ranges: one table for reading and
// validating (and in the order a start-up line names the defaults).
struct RobustKey {
  const char* key;
  double RobustConfig::*member;
  double lo, hi;
  bool lo_open;
};
constexpr RobustKey kRobustKeys[] = {
    {"detect_window", &RobustConfig::detect_window, 0.0, 10.0, true},
    {"long_window", &RobustConfig::long_window, 0.0, 10.0, false},
    {"chunk", &RobustConfig::chunk, 0.0, 10.0, true},
    {"threshold", &RobustConfig::threshold, 0.0, 100.0, true},
    {"noise_factor", &RobustConfig::noise_factor, 0.0, 1000.0, false},
    {"noise_time", &RobustConfig::noise_time, 0.0, 1e6, true},
    {"verify_time", &RobustConfig::verify_time, 0.0, 10.0, true},
    {"margin", &RobustConfig::margin, 0.0, 1.0, false},
    {"significance", &RobustConfig::significance, 0.0, 1e6, false},
    {"prior_std", &RobustConfig::prior_std, 0.0, 1e6, true},
    {"ridge", &RobustConfig::ridge, 0.0, 1e6, false},
    {"cl_gain", &RobustConfig::cl_gain, 0.0, 1e6, false},
    {"merge_tolerance", &RobustConfig::merge_tolerance, 0.0, 100.0, false},
    {"settle_time", &RobustConfig::settle_time, 0.0, 1e6, false},
    {"quiet_time", &RobustConfig::quiet_time, 0.0, 1e6, true},
    {"network_rate", &RobustConfig::network_rate, 0.0, 1e3, false},
};
}  // namespace

RobustConfig RobustConfig::read(ParamReader& r, const std::string& p) {
  RobustConfig c;
  if (!r.has(p)) {  // optional section: the documented defaults
    r.noteDefault(p, "absent (pa_robust's documented defaults)");
    return c;
  }
  // Each key is optional: an absent one keeps its documented default (noted, so the tools
  // and nodes print it), so `--set controller.robust.margin=0.3` works on any file.
  for (const RobustKey& k : kRobustKeys)
    c.*(k.member) = r.getDouble(p + "." + k.key, c.*(k.member));
  c.memory_size = static_cast<int>(r.getInt(p + ".memory_size", c.memory_size));
  c.use_network = r.getBool(p + ".use_network", c.use_network);
  return c;
}

void RobustConfig::validate(ParamReader& r, const std::string& p) const {
  auto range = [&](const std::string& key, double v, double lo, double hi, bool lo_open) {
    const std::string k = p + "." + key;
    if (!r.usable(k)) return;
    const bool ok = (lo_open ? v > lo : v >= lo) && v <= hi;
    if (!ok)
      r.fail(k, std::string("must be in ") + (lo_open ? "(" : "[") + formatNumber(lo) + ", " +
                    formatNumber(hi) + "], got " + formatNumber(v));
  };
  for (const RobustKey& k : kRobustKeys) range(k.key, this->*(k.member), k.lo, k.hi, k.lo_open);
  range("memory_size", memory_size, 0.0, 1024.0, false);
  // The pairs are checked when either key is given (the other may be its default).
  auto pair = [&](const std::string& a, const std::string& b) {
    return (r.has(p + a) || r.has(p + b)) && !r.failed(p + a) && !r.failed(p + b);
  };
  if (pair(".verify_time", ".detect_window") && verify_time < detect_window)
    r.fail(p + ".verify_time", "must be >= detect_window (" + formatNumber(detect_window) +
                                   "), got " + formatNumber(verify_time));
  if (pair(".long_window", ".detect_window") && long_window > 0.0 && long_window < detect_window)
    r.fail(p + ".long_window", "must be 0 (off) or >= detect_window (" +
                                   formatNumber(detect_window) + "), got " +
                                   formatNumber(long_window));
  if (pair(".chunk", ".verify_time") && chunk > verify_time)
    r.fail(p + ".chunk", "must be <= verify_time (" + formatNumber(verify_time) + "), got " +
                             formatNumber(chunk));
}

ControllerConfig ControllerConfig::read(ParamReader& r, int n, const std::string& p) {
  ControllerConfig c;
  const std::string mode = r.getString(p + ".mode");
  if (r.has(p + ".mode")) {
    auto m = parseMode(mode);
    if (m) {
      c.mode = *m;
    } else if (!mode.empty() || r.has(p + ".mode")) {
      r.fail(p + ".mode",
             "expected one of rac, pa, pa_learn, pa_learn_exact, pa_robust, oracle, l1, got '" +
                 mode + "'");
    }
  }
  c.sample_time = r.getDouble(p + ".sample_time");
  c.Q = r.getMatrix(p + ".lqr.Q", n > 0 ? n : -1, n > 0 ? n : -1);
  c.R = r.getDouble(p + ".lqr.R");
  c.k0 = r.getDouble(p + ".reference_model.k0");
  c.gamma = r.getDouble(p + ".adaptation.gamma");
  c.theta_hat0 = r.getVector(p + ".adaptation.theta_hat0", n > 0 ? n : -1);
  c.tau = r.getDouble(p + ".velocity_estimator.tau");
  c.c_e = r.getDouble(p + ".attention.c_e");
  c.c_ed = r.getDouble(p + ".attention.c_ed");
  c.hidden = static_cast<int>(r.getInt(p + ".preadaptation.hidden"));
  c.init_scale = r.getDouble(p + ".preadaptation.init_scale");
  const std::int64_t seed = r.getInt(p + ".preadaptation.seed");
  if (seed < 0) r.fail(p + ".preadaptation.seed", "must be >= 0, got " + std::to_string(seed));
  c.seed = static_cast<std::uint64_t>(seed < 0 ? 0 : seed);
  c.gamma_pa = r.getDouble(p + ".preadaptation.gamma_pa");
  // Options beyond the paper: optional, and their defaults reproduce the paper.
  c.confirm_samples = static_cast<int>(r.getInt(p + ".attention.confirm_samples", 0));
  c.hysteresis = r.getDouble(p + ".attention.hysteresis", 0.0);
  c.freeze_when_saturated = r.getBool(p + ".adaptation.freeze_when_saturated", true);
  if (r.has(p + ".projection")) {
    c.projection = r.getBool(p + ".projection.enabled");
    c.theta_max = r.getDouble(p + ".projection.theta_max");
    c.projection_epsilon = r.getDouble(p + ".projection.epsilon");
  } else {
    r.noteDefault(p + ".projection", "absent (no projection)");
  }
  c.robust = RobustConfig::read(r, p + ".robust");
  c.l1 = L1Config::read(r, p + ".l1");
  c.validate(r, n, p);
  return c;
}

void ControllerConfig::validate(ParamReader& r, int n, const std::string& p) const {
  auto positive = [&](const std::string& key, double v) {
    if (r.usable(key) && !(v > 0.0)) r.fail(key, "must be > 0, got " + formatNumber(v));
  };
  positive(p + ".sample_time", sample_time);
  positive(p + ".lqr.R", R);
  positive(p + ".adaptation.gamma", gamma);
  positive(p + ".attention.c_e", c_e);
  positive(p + ".attention.c_ed", c_ed);
  positive(p + ".preadaptation.gamma_pa", gamma_pa);
  if (r.usable(p + ".velocity_estimator.tau") && !(tau >= 0.0))
    r.fail(p + ".velocity_estimator.tau", "must be >= 0, got " + formatNumber(tau));
  if (r.usable(p + ".preadaptation.init_scale") && !(init_scale >= 0.0))
    r.fail(p + ".preadaptation.init_scale", "must be >= 0, got " + formatNumber(init_scale));
  if (r.usable(p + ".preadaptation.hidden") && (hidden < 1 || hidden > kMaxHidden))
    r.fail(p + ".preadaptation.hidden",
           "must be in [1, " + std::to_string(kMaxHidden) + "], got " + std::to_string(hidden));
  if (r.usable(p + ".attention.confirm_samples") && confirm_samples < 0)
    r.fail(p + ".attention.confirm_samples",
           "must be >= 0, got " + std::to_string(confirm_samples));
  if (r.usable(p + ".attention.hysteresis") && !(hysteresis >= 0.0 && hysteresis < c_e))
    r.fail(p + ".attention.hysteresis",
           "must be in [0, c_e = " + formatNumber(c_e) + "), got " + formatNumber(hysteresis));
  if (r.has(p + ".projection")) {
    positive(p + ".projection.theta_max", theta_max);
    if (r.usable(p + ".projection.epsilon") &&
        !(projection_epsilon > 0.0 && projection_epsilon <= 1.0))
      r.fail(p + ".projection.epsilon",
             "must be in (0, 1], got " + formatNumber(projection_epsilon));
    if (projection && theta_hat0.size() > 0 && r.usable(p + ".adaptation.theta_hat0") &&
        theta_hat0.norm() > theta_max)
      r.fail(p + ".adaptation.theta_hat0",
             "lies outside Omega (norm " + formatNumber(theta_hat0.norm()) + " > theta_max)");
  }
  if (r.has(p + ".robust")) robust.validate(r, p + ".robust");
  if (r.has(p + ".l1")) l1.validate(r, p + ".l1", sample_time);
  if (n > 0 && Q.rows() == n && Q.cols() == n && r.usable(p + ".lqr.Q")) {
    if ((Q - Q.transpose()).norm() > 1e-12 * std::max(1.0, Q.norm()))
      r.fail(p + ".lqr.Q", "must be symmetric");
    else if (Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Q).eigenvalues().minCoeff() <
             -1e-12 * std::max(1.0, Q.norm()))
      r.fail(p + ".lqr.Q", "must be positive semi-definite");
  }
}

double VelocityEstimator::update(double e) {
  if (!primed_) {
    primed_ = true;
    prev_ = e;
    value_ = 0.0;
    return value_;
  }
  value_ = (tau_ * value_ + (e - prev_)) / (tau_ + dt_);
  prev_ = e;
  return value_;
}

Attention::Result Attention::decideUp(double e_dot) {
  if (!(std::abs(e_dot) > c_ed_)) return Result::kNone;
  if (active_) return Result::kIgnoredOnset;
  active_ = true;
  return Result::kOnset;
}

Attention::Result Attention::decideDown(double e_dot) {
  if (!(std::abs(e_dot) < c_ed_)) return Result::kNone;
  if (!active_) return Result::kIgnoredRecovery;
  active_ = false;
  return Result::kRecovered;
}

void Attention::setThresholds(double c_e, double c_ed, int confirm_samples, double hysteresis) {
  if (confirm_samples != confirm_) up_count_ = down_count_ = -1;
  c_e_ = c_e;
  c_ed_ = c_ed;
  confirm_ = confirm_samples;
  hyst_ = hysteresis;
  if (primed_) {  // the last sample against the new thresholds: the change is no crossing
    s_prev_ = abs_e_prev_ - c_e_;
    d_prev_ = abs_e_prev_ - (c_e_ - hyst_);
  }
}

Attention::Result Attention::update(double e, double e_dot) {
  abs_e_prev_ = std::abs(e);
  const double s = std::abs(e) - c_e_;            // onset threshold
  const double d = std::abs(e) - (c_e_ - hyst_);  // recovery threshold
  if (!primed_) {
    primed_ = true;
    s_prev_ = s;
    d_prev_ = d;
    return Result::kNone;
  }
  const bool up = s_prev_ < 0.0 && s >= 0.0;
  const bool down = d_prev_ > 0.0 && d <= 0.0;
  s_prev_ = s;
  d_prev_ = d;
  if (confirm_ == 0) {  // the paper: decide at the crossing sample
    if (up) return decideUp(e_dot);
    if (down) return decideDown(e_dot);
    return Result::kNone;
  }
  // Debounced: a crossing is pending until |e| has stayed on its new side confirm_ samples.
  if (up) up_count_ = 0;
  if (down) down_count_ = 0;
  if (up_count_ >= 0) {
    if (s < 0.0) {
      up_count_ = -1;
    } else if (!up && ++up_count_ >= confirm_) {
      up_count_ = -1;
      return decideUp(e_dot);
    }
  }
  if (down_count_ >= 0) {
    if (d > 0.0) {
      down_count_ = -1;
    } else if (!down && ++down_count_ >= confirm_) {
      down_count_ = -1;
      return decideDown(e_dot);
    }
  }
  return Result::kNone;
}

SensitivityTracker::SensitivityTracker(const Mat& Ar, const Vec& B, const Vec& PB, double gamma,
                                       int out)
    : Ar_(Ar), B_(B), PB_(PB), gamma_(gamma), out_(out), n_(static_cast<int>(Ar.rows())) {
  S_.setZero(2 * n_, n_);
  Sdot_.setZero(2 * n_, n_);
  g_.setZero(n_);
}

void SensitivityTracker::start() {
  S_.setZero(2 * n_, n_);
  S_.bottomRows(n_).setIdentity();
  E_ = 0.0;
  g_.setZero(n_);
}

PiMat SensitivityTracker::pi(const Vec& ev, const Vec& x, const Vec& theta_err) const {
  PiMat P = PiMat::Zero(2 * n_, 2 * n_);
  P.topLeftCorner(n_, n_) = Ar_ + B_ * theta_err.transpose();
  P.topRightCorner(n_, n_) = -B_ * x.transpose();
  P.bottomLeftCorner(n_, n_) =
      gamma_ * ev.dot(PB_) * Mat::Identity(n_, n_) + gamma_ * x * PB_.transpose();
  return P;
}

void SensitivityTracker::accumulate(double dt, const Vec& ev, const Vec& x, const Vec& theta_err) {
  const double e = ev[out_];
  E_ += std::abs(e) * dt;
  const double sgn = (e > 0.0) - (e < 0.0);
  if (fastThree(n_)) {
    accumulate3(dt, sgn, ev, x, theta_err);
    return;
  }
  g_ += (sgn * dt) * S_.row(out_).transpose();
  // S_dot = Pi S without forming Pi: the blocks are rank-one updates of A_r and the identity.
  const auto top = S_.topRows(n_);
  const auto bot = S_.bottomRows(n_);
  Eigen::Matrix<double, 1, Eigen::Dynamic, Eigen::RowMajor, 1, kMaxStates> row1, row2, row3;
  row1.noalias() = theta_err.transpose().lazyProduct(top);
  row2.noalias() = x.transpose().lazyProduct(bot);
  row3.noalias() = PB_.transpose().lazyProduct(top);
  Sdot_.topRows(n_).noalias() = Ar_.lazyProduct(top);
  Sdot_.topRows(n_).noalias() += B_ * (row1 - row2);
  Sdot_.bottomRows(n_) = (gamma_ * ev.dot(PB_)) * top;
  Sdot_.bottomRows(n_).noalias() += gamma_ * x * row3;
  S_ += dt * Sdot_;
}

// accumulate() written out for three states, each sum in the order of Eigen's expressions
// above (test_fast_paths compares the two): the lazy products summed from index 0 up, the
// outer products added after them, B_i (row1 - row2)_j and row3_j (gamma x_i).
void SensitivityTracker::accumulate3(double dt, double sgn, const Vec& ev, const Vec& x,
                                     const Vec& theta_err) {
  const double c = sgn * dt;
  for (int j = 0; j < 3; ++j) g_[j] += c * S_(out_, j);
  double row1[3], row2[3], row3[3];
  for (int j = 0; j < 3; ++j) {
    row1[j] = (theta_err[0] * S_(0, j) + theta_err[1] * S_(1, j)) + theta_err[2] * S_(2, j);
    row2[j] = (x[0] * S_(3, j) + x[1] * S_(4, j)) + x[2] * S_(5, j);
    row3[j] = (PB_[0] * S_(0, j) + PB_[1] * S_(1, j)) + PB_[2] * S_(2, j);
  }
  const double ce = gamma_ * dotOf(ev, PB_);
  const double gx[3] = {gamma_ * x[0], gamma_ * x[1], gamma_ * x[2]};
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      Sdot_(i, j) = ((Ar_(i, 0) * S_(0, j) + Ar_(i, 1) * S_(1, j)) + Ar_(i, 2) * S_(2, j)) +
                    B_[i] * (row1[j] - row2[j]);
      Sdot_(3 + i, j) = ce * S_(i, j) + row3[j] * gx[i];
    }
  }
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 6; ++i) S_(i, j) += dt * Sdot_(i, j);
}

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

ControllerTunables ControllerTunables::of(const ControllerConfig& c) {
  ControllerTunables t;
  t.c_e = c.c_e;
  t.c_ed = c.c_ed;
  t.confirm_samples = c.confirm_samples;
  t.hysteresis = c.hysteresis;
  t.gamma = c.gamma;
  t.gamma_pa = c.gamma_pa;
  t.projection = c.projection;
  t.theta_max = c.theta_max;
  t.projection_epsilon = c.projection_epsilon;
  t.robust = c.robust;
  return t;
}

void ControllerTunables::applyTo(ControllerConfig* c) const {
  c->c_e = c_e;
  c->c_ed = c_ed;
  c->confirm_samples = confirm_samples;
  c->hysteresis = hysteresis;
  c->gamma = gamma;
  c->gamma_pa = gamma_pa;
  c->projection = projection;
  c->theta_max = theta_max;
  c->projection_epsilon = projection_epsilon;
  c->robust = robust;
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
