#include "preadaptive_mrac/core/robust/robust_preadaptation.hpp"

#include <algorithm>
#include <cmath>

#include "preadaptive_mrac/core/control/attention.hpp"
#include "preadaptive_mrac/core/control/design_model.hpp"
#include "preadaptive_mrac/core/control/mode_context.hpp"
#include "preadaptive_mrac/core/robust/regime_decision.hpp"
#include "preadaptive_mrac/core/small_ops.hpp"
#include "preadaptive_mrac/core/solvers.hpp"

namespace preadaptive_mrac {

namespace {
int samplesOf(double seconds, double dt) {
  return std::max(1, static_cast<int>(std::lround(seconds / dt)));
}
}  // namespace

RobustPreadaptation::RobustPreadaptation(const ControllerParams& cfg, const RobustParams& robust,
                                         const Eigen::MatrixXd& A, const Eigen::VectorXd& B,
                                         const Eigen::VectorXd& B1r, const Vec& K,
                                         PreadaptNetwork* net)
    : rc_(robust),
      K_(K),
      projection_(cfg.projection),
      theta_max_(cfg.theta_max),
      dt_(cfg.sample_time),
      A_(A),
      B_(B),
      B1r_(B1r),
      bb_(B.squaredNorm()),
      net_(net),
      loss_(static_cast<int>(B.size())) {
  sizeWindows();
  const int n = static_cast<int>(B.size());
  win_.resize(cap_, Ll_, n);
  x_prev_.setZero(n);
  theta_keep_.setZero(n);
  theta_net_.setZero(n);
  regime_.clear(n);
  prior_.setZero(n);
  net_->state().regimes.reserve(static_cast<size_t>(std::max(rc_.memory_size, 0)) + 1);
  reset();
}

void RobustPreadaptation::sizeWindows() {
  Ld_ = samplesOf(rc_.detect_window, dt_);
  Lc_ = samplesOf(rc_.chunk, dt_);
  Lv_ = samplesOf(rc_.verify_time, dt_);
  Lq_ = samplesOf(rc_.quiet_time, dt_);
  Ls_ = samplesOf(rc_.settle_time, dt_);
  Lw_ = samplesOf(rc_.min_dwell, dt_);
  Ll_ = rc_.long_window > 0.0 ? std::max(Ld_, samplesOf(rc_.long_window, dt_)) : 0;
  cap_ = std::max({2 * Ld_, Lv_ + 2 * Ld_, 2 * Ll_}) + 2;
}

bool RobustPreadaptation::setTunables(const ControllerParams& cfg, const RobustParams& robust) {
  const int ld = Ld_, lc = Lc_, lv = Lv_, ll = Ll_;
  rc_ = robust;
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
  regime_.c = 0.0;
  next_chunk_k_ = 0;
  rho_long_ = 0.0;
  long_trigger_ = false;
  nu_regime_ = nu_decided_ = 0.0;
  loss_.restart(-1);
  loss_.clearBlock();
  t_prev_ = 0.0;
  // The regime flown from the start is identified as one after an onset.
  excite_until_ = rc_.excitation_time;
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
  // The loss fit's sample covers [t_prev, t_k]: the command there carried excitation(t_prev).
  if (sample && rc_.excitation > 0.0 && rc_.loss_max > 0.0)
    loss_.add(k_, excitationHalf(t_prev_), phi_k, y_k, v_k, excitation(t_prev_) * dt_);
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
  if (std::abs(rho_) > thr && k_ - last_trigger_k_ >= std::max(Ld_, Lw_)) {
    long_trigger_ = false;
    return Detection::kOnset;
  }
  // The long window: a small mismatch that stays under the short window's noise-raised
  // threshold for long. Its noise is endpoint noise, Ld_ / Ll_ of the short window's; it sees
  // only data since the last reset (older data is judged against a theta_hat it did not have).
  if (Ll_ > Ld_ && win_.count() >= Ll_ && k_ - last_trigger_k_ >= std::max(Ll_, Lw_) &&
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
  loss_.restart(-1);

  // Probe the elevator while this regime is identified, not in the steady flight after it.
  if (rc_.excitation_time > 0.0) excite_until_ = s.t + rc_.excitation_time;
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
    regime_.clear(B_.size());
    const int m = static_cast<int>(std::min<std::int64_t>(k_ - post_start_k_ + 1, win_.count()));
    addChunks(&regime_, m, true);
    // The regime's fit aims with the loss the last decision used (a recalled entry's).
    nu_regime_ = nu_decided_;
    loss_.restart(k_);
    prior_ = *theta_hat;
    next_chunk_k_ = k_ + Lc_;
  }
}

int RobustPreadaptation::addChunks(ChunkSums* sums, int m, bool with_loss) const {
  int chunks = 0;
  for (int j0 = m - 1; j0 >= 0; j0 -= Lc_, ++chunks) {
    const int len = std::min(Lc_, j0 + 1);
    sums->add(win_, j0 - len + 1, len, with_loss);
  }
  return chunks;
}

double RobustPreadaptation::chunkSigma() const {
  // The noise of a chunk sum is endpoint noise, the same as of a detection-window sum; a floor
  // of a tenth of the threshold keeps clean data from acting on round-off.
  return std::max(noiseLevel() * Ld_ * dt_, 0.1 * rc_.threshold * Lc_ * dt_);
}

bool RobustPreadaptation::refine(Vec* theta_hat) {
  if (!regime_fit_ || verifying_ || k_ < next_chunk_k_) return false;
  next_chunk_k_ += Lc_;
  regime_.add(win_, 0, Lc_, nu_regime_ > 0.0);
  // With a loss nu the data reads y = (1 - nu) th^T phi + nu (theta_rec^T phi + ...) for the
  // loop's fixed point th: the fit aims at th through (Y - nu v) / (1 - nu).
  const double nu = nu_regime_;
  // Bayesian least squares of the regime's data around the prior (the decision's estimate):
  // excited directions follow the data, unexcited ones stay at the prior.
  const Vec fit =
      ridgeFit(regime_.G, regime_.hFixed(nu), prior_, chunkSigma(), rc_.prior_std, rc_.ridge);
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
  // A remembered regime with a loss nu is judged by the data it predicts while theta_hat is
  // still elsewhere: for the loop's fixed point th, y = (1 - nu) th^T phi + nu V (LossSums).
  RegimeMemory mem = memory();
  DecisionCandidates cand;
  cand.keep = theta_keep_;
  bool any_loss = false;
  for (int i = 0; i < mem.size(); ++i) {
    cand.memory.push_back(mem.at(i).theta);
    cand.memory_loss.push_back(entryLoss(mem.at(i)));
    any_loss = any_loss || cand.memory_loss.back() > 0.0;
  }
  cand.use_network = rc_.use_network;
  if (cand.use_network) cand.network = theta_net_;
  // Post-change data in chunks, and its plain sums.
  const int m = static_cast<int>(std::min<std::int64_t>(k_ - post_start_k_ + 1, win_.count()));
  DecisionData data;
  data.chunks.clear(B_.size());
  const int chunks = addChunks(&data.chunks, m, any_loss);
  win_.sums(0, m, &data.phi_tot, &data.y_tot);
  DecisionSettings set;
  set.sigma = chunkSigma();
  set.z = std::sqrt(rc_.significance);  // in standard deviations
  set.margin = rc_.margin;
  set.prior_std = rc_.prior_std;
  set.ridge = rc_.ridge;
  set.first_move = first_move_;
  set.clip = k_ < verify_end_k_;
  const DecisionResult res = decideRegime(data, cand, set);

  const Event::Decision kind = res.kind;
  nu_decided_ = res.nu;
  if (kind != Event::Decision::kKeep) first_move_ = false;
  recalled_ = kind == Event::Decision::kMemory ? res.chosen : -1;
  if (kind != Event::Decision::kKeep) {
    *theta_hat = res.theta;
    if (projection_) clampToBall(theta_hat, theta_max_);
    ev->reset = true;
  }
  ev->decision = kind;
  ev->chosen = res.chosen;
  ev->candidates = res.candidates;
  const double Tc = Lc_ * dt_;
  const double norm = 1.0 / (std::sqrt(static_cast<double>(std::max(chunks, 1))) * Tc);
  ev->score =
      std::sqrt(kind == Event::Decision::kKeep ? res.error_keep : data.chunks.error(*theta_hat)) *
      norm;
  ev->score_keep = std::sqrt(res.error_keep) * norm;
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
  if (rc_.excitation_time > 0.0 && !(t < excite_until_)) return 0.0;
  return excitationHalf(t) % 2 == 0 ? rc_.excitation : -rc_.excitation;
}

std::pair<double, double> RobustPreadaptation::lossFit() const {
  if (rc_.loss_max <= 0.0 || rc_.excitation <= 0.0) return {0.0, 0.0};
  return loss_.fit(chunkSigma());
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
  return std::make_unique<RobustPreadaptation>(*m.cfg, *m.robust, m.model->A, *m.B, m.model->B1r,
                                               Vec(m.design->K.transpose()), m.net);
}

}  // namespace preadaptive_mrac
