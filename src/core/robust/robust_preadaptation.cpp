#include "preadaptive_mrac/core/robust/robust_preadaptation.hpp"

#include <algorithm>
#include <cmath>

#include "preadaptive_mrac/core/control/attention.hpp"
#include "preadaptive_mrac/core/control/mode_context.hpp"
#include "preadaptive_mrac/core/small_ops.hpp"
#include "preadaptive_mrac/core/solvers.hpp"

namespace preadaptive_mrac {

namespace {
int samplesOf(double seconds, double dt) {
  return std::max(1, static_cast<int>(std::lround(seconds / dt)));
}
}  // namespace

RobustPreadaptation::RobustPreadaptation(const ControllerConfig& cfg, const PlantConfig& plant,
                                         const Vec& K, PreadaptNetwork* net)
    : rc_(cfg.robust),
      K_(K),
      projection_(cfg.projection),
      theta_max_(cfg.theta_max),
      dt_(cfg.sample_time),
      A_(plant.A),
      B_(plant.B),
      B1r_(plant.B1r),
      bb_(plant.B.squaredNorm()),
      net_(net) {
  sizeWindows();
  const int n = plant.n();
  win_.resize(cap_, Ll_, n);
  x_prev_.setZero(n);
  theta_keep_.setZero(n);
  theta_net_.setZero(n);
  Gr_.setZero(n, n);
  hr_.setZero(n);
  regime_v_.hv.setZero(n);
  prior_.setZero(n);
  block_.phi.setZero(n);
  pending_block_.phi.setZero(n);
  net_->state().regimes.reserve(static_cast<size_t>(std::max(rc_.memory_size, 0)) + 1);
  reset();
}

void RobustPreadaptation::sizeWindows() {
  Ld_ = samplesOf(rc_.detect_window, dt_);
  Lc_ = samplesOf(rc_.chunk, dt_);
  Lv_ = samplesOf(rc_.verify_time, dt_);
  Lq_ = samplesOf(rc_.quiet_time, dt_);
  Ls_ = samplesOf(rc_.settle_time, dt_);
  Ll_ = rc_.long_window > 0.0 ? std::max(Ld_, samplesOf(rc_.long_window, dt_)) : 0;
  cap_ = std::max({2 * Ld_, Lv_ + 2 * Ld_, 2 * Ll_}) + 2;
}

bool RobustPreadaptation::setTunables(const ControllerConfig& cfg) {
  const int ld = Ld_, lc = Lc_, lv = Lv_, ll = Ll_;
  rc_ = cfg.robust;
  projection_ = cfg.projection;
  theta_max_ = cfg.theta_max;
  sizeWindows();
  net_->state().regimes.reserve(static_cast<size_t>(std::max(rc_.memory_size, 0)) + 1);
  const int before = memory().size();
  memory().trim();
  if (memory().size() != before) recalled_ = -1;  // indices moved
  if (Ld_ == ld && Lc_ == lc && Lv_ == lv && Ll_ == ll) return false;
  // The ring's sums and the detection statistics are per window: start them again.
  win_.resize(cap_, Ll_, B_.size());
  reset();
  return true;
}

void RobustPreadaptation::reset() {
  win_.clear();
  k_ = 0;
  have_prev_ = false;
  rho_ = 0.0;
  dev_ = 0.0;
  dev_init_ = false;
  noise_blocks_ = 0;
  last_trigger_k_ = -1000000000;
  verifying_ = false;
  post_start_k_ = verify_end_k_ = next_decision_k_ = regime_start_k_ = 0;
  quiet_ = 0;
  recalled_ = -1;
  phase_cost_ = 0.0;
  regime_fit_ = false;
  cr_ = 0.0;
  next_chunk_k_ = 0;
  rho_long_ = 0.0;
  long_trigger_ = false;
  nu_regime_ = nu_decided_ = 0.0;
  lossReset(-1);
  block_.phi.setZero(B_.size());
  block_.y = block_.v = block_.d = 0.0;
  block_.start_k = 0;
  block_half_ = 0;
  t_prev_ = 0.0;
}

RegimeMemory RobustPreadaptation::memory() {
  return RegimeMemory(&net_->state().regimes, rc_.memory_size);
}

// The generic branch of detect() written out for three states. Eigen evaluates A xm as a
// matrix-vector product (GEMV): each row accumulated from 0 over the columns and then added
// to the zeroed destination; the rest is element-wise.
void RobustPreadaptation::residualSample3(const Vec& x, double u_prev, double r_prev, Vec* phi,
                                          Vec* d) const {
  const double xm[3] = {0.5 * (x_prev_[0] + x[0]), 0.5 * (x_prev_[1] + x[1]),
                        0.5 * (x_prev_[2] + x[2])};
  phi->resize(3);
  d->resize(3);
  for (int i = 0; i < 3; ++i) {
    double c = A_(i, 0) * xm[0] + 0.0;
    c = A_(i, 1) * xm[1] + c;
    c = A_(i, 2) * xm[2] + c;
    const double f = c + 0.0;
    (*d)[i] = (x[i] - x_prev_[i]) - dt_ * ((f + B_[i] * u_prev) + B1r_[i] * r_prev);
    (*phi)[i] = dt_ * xm[i];
  }
}

double RobustPreadaptation::triggerThreshold() const {
  return std::max(rc_.threshold, rc_.noise_factor * noiseLevel());
}

Detection RobustPreadaptation::detect(const Sample& s, const Vec& theta_hat, Attention* attention) {
  (void)attention;
  const Vec& x = *s.x;
  Vec phi_k, d;
  double y_k = 0.0, v_k = 0.0;
  const bool sample = have_prev_;
  if (have_prev_) {
    if (fastThree(x.size())) {
      residualSample3(x, s.u_prev, s.r_prev, &phi_k, &d);
    } else {
      Vec xm = 0.5 * (x_prev_ + x);
      d = x - x_prev_;
      Vec f;
      f.noalias() = A_ * xm;
      d -= dt_ * (f + B_ * s.u_prev + B1r_ * s.r_prev);
      phi_k = dt_ * xm;
    }
    y_k = dotOf(B_, d) / bb_;
    v_k = -s.u_prev * dt_ - K_.dot(phi_k);
    win_.push(phi_k, y_k, theta_hat, v_k);
  }
  copyTo(x, &x_prev_);
  have_prev_ = true;
  ++k_;
  if (sample) lossSample(t_prev_, phi_k, y_k, v_k);
  t_prev_ = s.t;
  if (win_.count() < Ld_) return Detection::kNone;

  const double Td = Ld_ * dt_;
  Vec phi;
  double y = 0.0;
  win_.sums(0, Ld_, &phi, &y);
  rho_ = (y - dotOf(theta_hat, phi)) / Td;
  const double thr = triggerThreshold();

  // Noise level from the change of the residual between adjacent windows: a constant mismatch
  // cancels, noise does not (E|delta| = 2 sigma / sqrt(pi)). Each step is clipped at four
  // times the estimate, so a switch barely moves it; paused while verifying.
  if (k_ % Ld_ == 0 && win_.count() >= 2 * Ld_ && !verifying_) {
    Vec phi_p;
    double y_p = 0.0;
    win_.sums(Ld_, Ld_, &phi_p, &y_p);
    const double delta = std::abs(rho_ - (y_p - dotOf(theta_hat, phi_p)) / Td);
    // A running mean over the first blocks, then an exponential one over noise_time.
    const double beta = std::max(1.0 / (noise_blocks_ + 1), std::min(1.0, Td / rc_.noise_time));
    if (!dev_init_) {
      dev_ = delta;
      dev_init_ = true;
    } else {
      dev_ += beta * (std::min(delta, std::max(4.0 * dev_, rc_.threshold)) - dev_);
    }
    ++noise_blocks_;
  }

  if (verifying_) return k_ >= next_decision_k_ ? Detection::kDecision : Detection::kNone;
  // No trigger before the noise level is known (kMinNoiseBlocks windows of data).
  if (noise_blocks_ < kMinNoiseBlocks) return Detection::kNone;
  if (std::abs(rho_) > thr && k_ - last_trigger_k_ >= Ld_) {
    long_trigger_ = false;
    return Detection::kOnset;
  }
  // The long window: a small mismatch that stays under the short window's noise-raised
  // threshold for long. Its noise is endpoint noise, Ld_ / Ll_ of the short window's; it sees
  // only data since the last reset (older data is judged against a theta_hat it did not have).
  if (Ll_ > Ld_ && win_.count() >= Ll_ && k_ - last_trigger_k_ >= Ll_ &&
      k_ - verify_end_k_ >= Ll_) {
    rho_long_ = (win_.yLong() - dotOf(theta_hat, win_.phiLong())) / (Ll_ * dt_);
    const double thr_long =
        std::max(rc_.threshold, rc_.noise_factor * noiseLevel() * static_cast<double>(Ld_) / Ll_);
    if (std::abs(rho_long_) > thr_long) {
      long_trigger_ = true;
      return Detection::kOnset;
    }
  }
  if (attention->phaseActive()) {
    quiet_ = std::abs(rho_) <= thr ? quiet_ + 1 : 0;
    if (quiet_ >= Lq_) return Detection::kRecovered;
  }
  return Detection::kNone;
}

void RobustPreadaptation::onOnset(const Sample& s, Vec* theta_hat, Event* ev) {
  // Where did the mismatch begin? The cumulative residual from the newest sample back grows
  // while the data is post-change and stays flat before: take the shortest span holding 90 %
  // of its largest excursion in the direction of the residual.
  const int span =
      long_trigger_ ? static_cast<int>(std::min<std::int64_t>(
                          {static_cast<std::int64_t>(win_.count()), 2 * Ll_, k_ - verify_end_k_}))
                    : std::min(win_.count(), std::max(2 * Ld_, 2));
  const double rho = long_trigger_ ? rho_long_ : rho_;
  const double sgn = rho >= 0.0 ? 1.0 : -1.0;
  double S = 0.0, best = 0.0;
  for (int j = 0; j < span; ++j) {
    const int i = win_.at(j);
    S += sgn * (win_.y(i) - theta_hat->dot(win_.phi(i)));
    best = std::max(best, S);
  }
  int m = span;
  S = 0.0;
  for (int j = 0; j < span; ++j) {
    const int i = win_.at(j);
    S += sgn * (win_.y(i) - theta_hat->dot(win_.phi(i)));
    if (S >= 0.9 * best) {
      m = j + 1;
      break;
    }
  }
  m = std::max(m, std::min(2, span));
  post_start_k_ = k_ - m + 1;
  // The estimate of the regime just left: theta_hat before the change.
  theta_keep_ = m < win_.count() ? win_.theta(win_.at(m)) : *theta_hat;

  // Bank the regime just left when it lasted long enough for the estimate to settle.
  if (k_ - regime_start_k_ >= Ls_ && win_.count() > m) {
    Vec dir;
    double ysum = 0.0;
    const int len = std::min(Ld_, win_.count() - m);
    win_.sums(m, len, &dir, &ysum);
    // With the loss of effectiveness fitted over the visit (pooled with the entry's).
    const std::pair<double, double> loss = lossFit();
    memory().remember(theta_keep_, dir / (len * dt_), rc_.merge_tolerance, loss.first, loss.second);
  }
  lossReset(-1);

  z_onset_ << s.e, std::abs(s.e_dot);
  if (rc_.use_network) net_->forward(z_onset_, &theta_net_);
  last_trigger_k_ = k_;
  regime_fit_ = false;
  verifying_ = true;
  first_move_ = true;
  verify_end_k_ = k_ + Lv_;
  next_decision_k_ = k_ + Lc_;
  quiet_ = 0;
  recalled_ = -1;
  phase_cost_ = 0.0;
  if (m >= Lc_) {
    decide(theta_hat, ev);
  } else {  // too little post-change data to decide on: the first decision comes with a chunk
    next_decision_k_ = post_start_k_ + Lc_ - 1;
  }
}

void RobustPreadaptation::onDecision(const Sample& s, Vec* theta_hat, Event* ev) {
  (void)s;
  decide(theta_hat, ev);
  next_decision_k_ += Lc_;
  if (k_ >= verify_end_k_) {
    verifying_ = false;
    quiet_ = 0;
    regime_start_k_ = post_start_k_;
    if (recalled_ >= 0) memory().markUsed(recalled_);
    // Concurrent learning from here on: the regime's data so far, then every new chunk.
    regime_fit_ = rc_.cl_gain > 0.0;
    Gr_.setZero();
    hr_.setZero();
    cr_ = 0.0;
    const int m = static_cast<int>(std::min<std::int64_t>(k_ - post_start_k_ + 1, win_.count()));
    regime_v_ = LossSums();
    regime_v_.hv.setZero(B_.size());
    for (int j0 = m - 1; j0 >= 0; j0 -= Lc_) {
      const int len = std::min(Lc_, j0 + 1);
      addChunk(&Gr_, &hr_, &cr_, j0 - len + 1, len, &regime_v_);
    }
    // The regime's fit aims with the loss the last decision used (a recalled entry's).
    nu_regime_ = nu_decided_;
    lossReset(k_);
    prior_ = *theta_hat;
    next_chunk_k_ = k_ + Lc_;
  }
}

void RobustPreadaptation::addChunk(Mat* G, Vec* h, double* c, int j0, int len, LossSums* ls) const {
  Vec Phi;
  double Y = 0.0;
  win_.sums(j0, len, &Phi, &Y);
  G->noalias() += Phi * Phi.transpose();
  *h += Y * Phi;
  *c += Y * Y;
  if (ls != nullptr) {
    const double V = win_.vSum(j0, len);
    ls->hv += V * Phi;
    ls->yv += Y * V;
    ls->vv += V * V;
    ls->v += V;
  }
}

double RobustPreadaptation::chunkSigma() const {
  // The noise of a chunk sum is endpoint noise, the same as of a detection-window sum; a floor
  // of a tenth of the threshold keeps clean data from acting on round-off.
  return std::max(noiseLevel() * Ld_ * dt_, 0.1 * rc_.threshold * Lc_ * dt_);
}

bool RobustPreadaptation::refine(Vec* theta_hat) {
  if (!regime_fit_ || verifying_ || k_ < next_chunk_k_) return false;
  next_chunk_k_ += Lc_;
  addChunk(&Gr_, &hr_, &cr_, 0, Lc_, nu_regime_ > 0.0 ? &regime_v_ : nullptr);
  // With a loss nu the data reads y = (1 - nu) th^T phi + nu (theta_rec^T phi + ...) for the
  // loop's fixed point th: the fit aims at th through (Y - nu v) / (1 - nu).
  const double nu = nu_regime_;
  const Vec h_fix = nu > 0.0 ? Vec((hr_ - nu * regime_v_.hv) / (1.0 - nu)) : hr_;
  // Bayesian least squares of the regime's data around the prior (the decision's estimate):
  // excited directions follow the data, unexcited ones stay at the prior.
  const double sigma = chunkSigma();
  const int n = static_cast<int>(B_.size());
  Mat Gl = Gr_;
  const double lambda =
      sigma * sigma / (rc_.prior_std * rc_.prior_std) + rc_.ridge * std::max(Gr_.trace(), 0.0);
  for (int i = 0; i < n; ++i) Gl(i, i) += lambda;
  const Vec fit = prior_ + Gl.ldlt().solve(h_fix - Gr_ * prior_);
  const double step = std::min(1.0, rc_.cl_gain * Lc_ * dt_);
  Vec next = *theta_hat + step * (fit - *theta_hat);
  // Do no harm along the recent data: the pull may not make theta_hat explain the last long
  // window worse than it did, beyond noise. The regime's fit also carries the data since the
  // change and its prior; along the direction the plant shows now, the recent data is the
  // better judge (on a steady state a drift along it builds an error that rac would not have).
  const int len = static_cast<int>(
      std::min<std::int64_t>({static_cast<std::int64_t>(Ll_), k_ - post_start_k_ + 1,
                              static_cast<std::int64_t>(win_.count())}));
  if (len > 0) {
    Vec phi;
    double y = 0.0;
    if (len == Ll_ && win_.count() >= Ll_) {
      // The whole long window: its running sums (push()), not a fresh sum of Ll_ samples
      // every chunk (that sum was a sixth of pa_robust's instructions).
      phi = win_.phiLong();
      y = win_.yLong();
    } else {
      win_.sums(0, len, &phi, &y);
    }
    if (nu > 0.0) y = (y - nu * win_.vSum(0, len)) / (1.0 - nu);
    const double pp = phi.squaredNorm();
    if (pp > 0.0) {
      const double r0 = y - theta_hat->dot(phi);
      const double r1 = y - next.dot(phi);
      const double allowed = std::max(std::abs(r0), std::sqrt(rc_.significance) * chunkSigma());
      if (std::abs(r1) > allowed) next += phi * ((r1 - (r1 > 0.0 ? allowed : -allowed)) / pp);
    }
  }
  *theta_hat = next;
  return true;
}

void RobustPreadaptation::decide(Vec* theta_hat, Event* ev) {
  const int n = static_cast<int>(B_.size());
  // A remembered regime with a loss nu is judged by the data it predicts while theta_hat is
  // still elsewhere: for the loop's fixed point th, y = (1 - nu) th^T phi + nu V (LossSums).
  RegimeMemory mem = memory();
  std::vector<double> loss(static_cast<size_t>(mem.size()), 0.0);
  bool any_loss = false;
  for (int i = 0; i < mem.size(); ++i) {
    loss[static_cast<size_t>(i)] = entryLoss(mem.at(i));
    any_loss = any_loss || loss[static_cast<size_t>(i)] > 0.0;
  }
  // Post-change data in chunks: G = sum Phi Phi^T, h = sum Phi Y, c = sum Y^2, so that the
  // identification error of any theta is J = c - 2 theta^T h + theta^T G theta.
  const int m = static_cast<int>(std::min<std::int64_t>(k_ - post_start_k_ + 1, win_.count()));
  Mat G = Mat::Zero(n, n);
  Vec h = Vec::Zero(n);
  double c = 0.0;
  LossSums ls;
  ls.hv.setZero(n);
  int chunks = 0;
  for (int j0 = m - 1; j0 >= 0; j0 -= Lc_, ++chunks) {
    const int len = std::min(Lc_, j0 + 1);
    addChunk(&G, &h, &c, j0 - len + 1, len, any_loss ? &ls : nullptr);
  }
  auto J = [&](const Vec& th) { return std::max(0.0, c - 2.0 * th.dot(h) + th.dot(G * th)); };
  // sum (Y - (1 - nu) th^T Phi - nu V)^2 = J(th) - 2 nu sum (Y - th^T Phi)(V - th^T Phi) + nu^2
  // sum (V - th^T Phi)^2.
  auto Jnu = [&](const Vec& th, double nu) {
    if (nu <= 0.0) return J(th);
    const double rw = ls.yv - th.dot(ls.hv) - th.dot(h) + th.dot(G * th);
    const double ww = ls.vv - 2.0 * th.dot(ls.hv) + th.dot(G * th);
    return std::max(0.0, J(th) - 2.0 * nu * rw + nu * nu * ww);
  };
  double nu_chosen = 0.0;
  const double sigma = chunkSigma();
  const double z = std::sqrt(rc_.significance);  // in standard deviations

  // A candidate beats keeping when its error is `margin` lower and the gain is beyond what
  // noise explains: if keeping were right, J_keep - J_cand = -D + 2 sum d_i eps_i with
  // d_i = (cand - keep)^T Phi_i and D = sum d_i^2, so noise alone gives 2 sigma sqrt(D).
  const double j_keep = J(theta_keep_);
  auto beats = [&](const Vec& cand, double jc) {
    const Vec d = cand - theta_keep_;
    const double D = std::max(0.0, d.dot(G * d));
    return jc < (1.0 - rc_.margin) * j_keep && j_keep - jc > z * 2.0 * sigma * std::sqrt(D);
  };
  Event::Decision kind = Event::Decision::kKeep;
  int chosen = -1;
  double j_best = j_keep;
  Vec base = theta_keep_;
  int candidates = 1;
  for (int i = 0; i < mem.size(); ++i, ++candidates) {
    const double nui = loss[static_cast<size_t>(i)];
    const double ji = Jnu(mem.at(i).theta, nui);
    if (ji < j_best && beats(mem.at(i).theta, ji)) {
      j_best = ji;
      kind = Event::Decision::kMemory;
      chosen = i;
      base = mem.at(i).theta;
      nu_chosen = nui;
    }
  }
  if (rc_.use_network) {
    ++candidates;
    const double jn = J(theta_net_);
    if (jn < j_best && beats(theta_net_, jn)) {
      j_best = jn;
      kind = Event::Decision::kNetwork;
      chosen = -1;
      base = theta_net_;
      nu_chosen = 0.0;
    }
  }
  // Fit what the data determines (Bayesian least squares around the chosen base): excited
  // directions follow the data, the others keep the base. Applied only when the gain is
  // beyond noise (chi-square with n degrees of freedom, `significance` per parameter).
  Mat Gr = G;
  const double lambda =
      sigma * sigma / (rc_.prior_std * rc_.prior_std) + rc_.ridge * std::max(G.trace(), 0.0);
  for (int i = 0; i < n; ++i) Gr(i, i) += lambda;
  // With a recalled loss the fit and the mean below aim at the fixed point: (Y - nu V) / (1 - nu).
  const Vec h_fix = nu_chosen > 0.0 ? Vec((h - nu_chosen * ls.hv) / (1.0 - nu_chosen)) : h;
  Vec fitted = base + Gr.ldlt().solve(h_fix - G * base);
  const double j_fit = Jnu(fitted, nu_chosen);
  // The fit moves the base only when the base's mean mismatch over all post-change data,
  // |sum Y - base^T sum Phi|, is beyond z standard deviations: the total's noise is endpoint
  // noise only (the sums telescope). So noise moves nothing, and a recalled regime that
  // explains the data is used as remembered.
  Vec phi_tot;
  double y_tot = 0.0;
  win_.sums(0, m, &phi_tot, &y_tot);
  if (nu_chosen > 0.0) y_tot = (y_tot - nu_chosen * ls.v) / (1.0 - nu_chosen);
  nu_decided_ = nu_chosen;
  if (std::abs(y_tot - base.dot(phi_tot)) > z * sigma && j_fit < j_best) {
    if (kind == Event::Decision::kKeep) kind = Event::Decision::kFit;
  } else {
    fitted = base;
  }
  // Minimum change along the data. What the post-change data determines best is the mean
  // mismatch, y_tot - theta^T phi_tot, yet early on its noise (that of two end samples over a
  // few ms) is tens of mrad of elevator: a candidate that fits the data no worse than noise
  // explains, or the fit itself, can over-compensate, a spike of the elevator. So while the
  // decisions are re-made, theta^T phi_tot moves from keeping towards the data only: the first
  // move no further than the data proves (the near end of its z-interval), later ones no
  // further than its mean; never the other way. The other directions keep what the candidate
  // and the fit say. The last decision, on verify_time of data, sets the estimate unclipped,
  // so the regime fit does not start from the clipped one.
  const double pp = phi_tot.squaredNorm();
  if (kind != Event::Decision::kKeep && pp > 0.0 && k_ < verify_end_k_) {
    const double vk = theta_keep_.dot(phi_tot);
    const double sgn = y_tot >= vk ? 1.0 : -1.0;
    const double kappa = first_move_ ? z : 0.0;
    const double reach = std::max(0.0, sgn * (y_tot - vk) - kappa * sigma);
    const double move = sgn * (fitted.dot(phi_tot) - vk);
    const double target = std::min(std::max(move, 0.0), reach);
    if (target != move) fitted += sgn * (target - move) / pp * phi_tot;
  }
  if (kind != Event::Decision::kKeep) first_move_ = false;
  recalled_ = kind == Event::Decision::kMemory ? chosen : -1;
  if (kind != Event::Decision::kKeep) {
    *theta_hat = fitted;
    if (projection_) clampToBall(theta_hat, theta_max_);
    ev->reset = true;
  }
  ev->decision = kind;
  ev->chosen = chosen;
  ev->candidates = candidates;
  const double Tc = Lc_ * dt_;
  const double norm = 1.0 / (std::sqrt(static_cast<double>(std::max(chunks, 1))) * Tc);
  ev->score = std::sqrt(kind == Event::Decision::kKeep ? j_keep : J(*theta_hat)) * norm;
  ev->score_keep = std::sqrt(j_keep) * norm;
}

double RobustPreadaptation::entryLoss(const RegimeEntry& e) const {
  // Only a loss `significance` (3 sigma) from 0; an elevator more effective than modelled
  // (nu < 0) is not used.
  if (rc_.loss_max <= 0.0 || !(e.loss_info > 0.0)) return 0.0;
  if (!(e.loss * std::sqrt(e.loss_info) > std::sqrt(rc_.significance))) return 0.0;
  return std::min(e.loss, rc_.loss_max);
}

std::int64_t RobustPreadaptation::excitationHalf(double t) const {
  return static_cast<std::int64_t>(std::floor(2.0 * t / rc_.excitation_period + 1e-9));
}

double RobustPreadaptation::excitation(double t) const {
  if (rc_.excitation <= 0.0) return 0.0;
  return excitationHalf(t) % 2 == 0 ? rc_.excitation : -rc_.excitation;
}

void RobustPreadaptation::lossReset(std::int64_t start_k) {
  const Eigen::Index n = B_.size() + 1;
  loss_start_k_ = start_k;
  ZX_.setZero(n, n);
  ZZ_.setZero(n, n);
  ZY_.setZero(n);
  pending_ = false;
  loss_blocks_ = 0;
}

void RobustPreadaptation::lossSample(double t_prev, const Vec& phi, double y, double v) {
  if (rc_.excitation <= 0.0 || rc_.loss_max <= 0.0) return;
  // The sample covers [t_prev, t_k]: the command there carried excitation(t_prev).
  const std::int64_t half = excitationHalf(t_prev);
  if (half != block_half_) {  // a flip: the block closes, the one before it joins the fit
    const Eigen::Index n = B_.size();
    if (pending_) {
      Vec z(n + 1), x(n + 1);
      z << pending_block_.phi, pending_block_.d;
      x << pending_block_.phi, pending_block_.v;
      ZX_.noalias() += z * x.transpose();
      ZZ_.noalias() += z * z.transpose();
      ZY_ += pending_block_.y * z;
      ++loss_blocks_;
    }
    pending_ = loss_start_k_ >= 0 && block_.start_k >= loss_start_k_;
    std::swap(pending_block_, block_);
    block_.phi.setZero(n);
    block_.y = block_.v = block_.d = 0.0;
    block_.start_k = k_;
    block_half_ = half;
  }
  block_.phi += phi;
  block_.y += y;
  block_.v += v;
  block_.d += excitation(t_prev) * dt_;
}

std::pair<double, double> RobustPreadaptation::lossFit() const {
  // Instrumental variables: y = c^T Phi + nu v over the blocks, instruments (Phi, D). The
  // measurement noise enters u through the feedback and correlates with the noise of y, so a
  // least-squares fit on v is biased; the excitation is known and independent of it. The
  // noise of a block sum is endpoint noise (chunkSigma()), whatever the block's length.
  constexpr int kMinBlocks = 4;
  if (rc_.loss_max <= 0.0 || rc_.excitation <= 0.0 || loss_blocks_ < kMinBlocks) return {0.0, 0.0};
  const Eigen::Index n = B_.size();
  Mat A = ZX_;
  const double ridge = 1e-12 * std::max(ZX_.topLeftCorner(n, n).trace(), 0.0);
  for (Eigen::Index i = 0; i < n; ++i) A(i, i) += ridge;
  const auto lu = A.fullPivLu();
  if (!lu.isInvertible()) return {0.0, 0.0};
  const Mat Ai = lu.inverse();
  const Vec beta = Ai * ZY_;
  const double sigma = chunkSigma();
  const double var = sigma * sigma * (Ai * ZZ_ * Ai.transpose())(n, n);
  if (!(var > 0.0) || !std::isfinite(beta[n])) return {0.0, 0.0};
  return {beta[n], 1.0 / var};
}

void RobustPreadaptation::duringPhase(const Sample& s, double u, const Vec& theta_hat) {
  (void)u;
  (void)theta_hat;
  phase_cost_ += std::abs(s.e) * dt_;
}

void RobustPreadaptation::onRecovery(const Sample& s, const Vec& theta_hat, Event* ev) {
  (void)s;
  ev->cost = phase_cost_;
  Vec dir;
  double ysum = 0.0;
  win_.sums(0, std::min(Ld_, win_.count()), &dir, &ysum);
  memory().remember(theta_hat, dir / (std::min(Ld_, win_.count()) * dt_), rc_.merge_tolerance);
  if (rc_.use_network && rc_.network_rate > 0.0) {
    // Supervised: move the network's prediction at this onset's input towards the regime's
    // settled estimate (E = |theta_I - theta_hat|^2 / 2, so dE/dtheta_I = theta_I - theta_hat).
    Vec pred;
    net_->forward(z_onset_, &pred);
    ev->grad = pred - theta_hat;
    net_->learn(z_onset_, ev->grad, rc_.network_rate);
    ev->learned = true;
  }
}

std::unique_ptr<PreadaptationStrategy> makeRobustPreadaptation(const ModeContext& m) {
  return std::make_unique<RobustPreadaptation>(*m.cfg, *m.plant, Vec(m.design->K.transpose()),
                                               m.net);
}

}  // namespace preadaptive_mrac
