#include "preadaptive_mrac/core/robust_preadaptation.hpp"

#include <algorithm>
#include <cmath>

#include "preadaptive_mrac/core/attention.hpp"
#include "preadaptive_mrac/core/mode_registry.hpp"
#include "preadaptive_mrac/core/small_ops.hpp"

namespace preadaptive_mrac {

namespace {
int samplesOf(double seconds, double dt) {
  return std::max(1, static_cast<int>(std::lround(seconds / dt)));
}
}  // namespace

RobustPreadaptation::RobustPreadaptation(const ControllerConfig& cfg, const PlantConfig& plant,
                                         PreadaptNetwork* net)
    : rc_(cfg.robust),
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
  phi_.assign(static_cast<size_t>(cap_), Vec::Zero(n));
  th_.assign(static_cast<size_t>(cap_), Vec::Zero(n));
  y_.assign(static_cast<size_t>(cap_), 0.0);
  x_prev_.setZero(n);
  theta_keep_.setZero(n);
  theta_net_.setZero(n);
  Gr_.setZero(n, n);
  hr_.setZero(n);
  prior_.setZero(n);
  phi_long_.setZero(n);
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
  const Eigen::Index n = B_.size();
  phi_.assign(static_cast<size_t>(cap_), Vec::Zero(n));
  th_.assign(static_cast<size_t>(cap_), Vec::Zero(n));
  y_.assign(static_cast<size_t>(cap_), 0.0);
  reset();
  return true;
}

void RobustPreadaptation::reset() {
  head_ = -1;
  count_ = 0;
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
  phi_long_.setZero();
  y_long_ = rho_long_ = 0.0;
  since_refresh_ = 0;
  long_trigger_ = false;
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

int RobustPreadaptation::at(int j) const { return ((head_ - j) % cap_ + cap_) % cap_; }

void RobustPreadaptation::push(const Vec& phi, double y, const Vec& theta_hat) {
  if (Ll_ > 0 && count_ >= Ll_) {  // the sample leaving the long window
    subtractFrom(phi_[static_cast<size_t>(at(Ll_ - 1))], &phi_long_);
    y_long_ -= y_[static_cast<size_t>(at(Ll_ - 1))];
  }
  head_ = (head_ + 1) % cap_;
  copyTo(phi, &phi_[static_cast<size_t>(head_)]);
  y_[static_cast<size_t>(head_)] = y;
  copyTo(theta_hat, &th_[static_cast<size_t>(head_)]);
  count_ = std::min(count_ + 1, cap_);
  if (Ll_ > 0) {
    addTo(phi, &phi_long_);
    y_long_ += y;
    // Rounding builds up in running sums: sum the window afresh every so often.
    if (++since_refresh_ >= 64 * Ll_ && count_ >= Ll_) {
      windowSums(0, Ll_, &phi_long_, &y_long_);
      since_refresh_ = 0;
    }
  }
}

void RobustPreadaptation::windowSums(int j0, int len, Vec* phi, double* y) const {
  // Newest to oldest, from 0: the order of these sums is part of the results.
  const Eigen::Index n = B_.size();
  phi->setZero(n);
  *y = 0.0;
  if (fastThree(n) && len > 0) {
    // The B-747: three running scalars instead of a run-time sized vector, and the ring index
    // of j + 1 as that of j less one, wrapping (at(j + 1), without its divisions).
    size_t i = static_cast<size_t>(at(j0));
    const size_t last = static_cast<size_t>(cap_) - 1;
    double p0 = 0.0, p1 = 0.0, p2 = 0.0, ys = 0.0;
    for (int c = 0; c < len; ++c) {
      const double* v = phi_[i].data();
      p0 += v[0];
      p1 += v[1];
      p2 += v[2];
      ys += y_[i];
      i = i == 0 ? last : i - 1;
    }
    (*phi)[0] = p0;
    (*phi)[1] = p1;
    (*phi)[2] = p2;
    *y = ys;
    return;
  }
  for (int j = j0; j < j0 + len; ++j) {
    *phi += phi_[static_cast<size_t>(at(j))];
    *y += y_[static_cast<size_t>(at(j))];
  }
}

double RobustPreadaptation::triggerThreshold() const {
  return std::max(rc_.threshold, rc_.noise_factor * noiseLevel());
}

Detection RobustPreadaptation::detect(const Sample& s, const Vec& theta_hat, Attention* attention) {
  (void)attention;
  const Vec& x = *s.x;
  if (have_prev_) {
    Vec phi, d;
    if (fastThree(x.size())) {
      residualSample3(x, s.u_prev, s.r_prev, &phi, &d);
    } else {
      Vec xm = 0.5 * (x_prev_ + x);
      d = x - x_prev_;
      Vec f;
      f.noalias() = A_ * xm;
      d -= dt_ * (f + B_ * s.u_prev + B1r_ * s.r_prev);
      phi = dt_ * xm;
    }
    push(phi, dotOf(B_, d) / bb_, theta_hat);
  }
  copyTo(x, &x_prev_);
  have_prev_ = true;
  ++k_;
  if (count_ < Ld_) return Detection::kNone;

  const double Td = Ld_ * dt_;
  Vec phi;
  double y = 0.0;
  windowSums(0, Ld_, &phi, &y);
  rho_ = (y - dotOf(theta_hat, phi)) / Td;
  const double thr = triggerThreshold();

  // Noise level from the change of the residual between adjacent windows: a constant mismatch
  // cancels, noise does not (E|delta| = 2 sigma / sqrt(pi)). Each step is clipped at four
  // times the estimate, so a switch barely moves it; paused while verifying.
  if (k_ % Ld_ == 0 && count_ >= 2 * Ld_ && !verifying_) {
    Vec phi_p;
    double y_p = 0.0;
    windowSums(Ld_, Ld_, &phi_p, &y_p);
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
  if (Ll_ > Ld_ && count_ >= Ll_ && k_ - last_trigger_k_ >= Ll_ && k_ - verify_end_k_ >= Ll_) {
    rho_long_ = (y_long_ - dotOf(theta_hat, phi_long_)) / (Ll_ * dt_);
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
  const int span = long_trigger_
                       ? static_cast<int>(std::min<std::int64_t>(
                             {static_cast<std::int64_t>(count_), 2 * Ll_, k_ - verify_end_k_}))
                       : std::min(count_, std::max(2 * Ld_, 2));
  const double rho = long_trigger_ ? rho_long_ : rho_;
  const double sgn = rho >= 0.0 ? 1.0 : -1.0;
  double S = 0.0, best = 0.0;
  for (int j = 0; j < span; ++j) {
    const int i = at(j);
    S += sgn * (y_[static_cast<size_t>(i)] - theta_hat->dot(phi_[static_cast<size_t>(i)]));
    best = std::max(best, S);
  }
  int m = span;
  S = 0.0;
  for (int j = 0; j < span; ++j) {
    const int i = at(j);
    S += sgn * (y_[static_cast<size_t>(i)] - theta_hat->dot(phi_[static_cast<size_t>(i)]));
    if (S >= 0.9 * best) {
      m = j + 1;
      break;
    }
  }
  m = std::max(m, std::min(2, span));
  post_start_k_ = k_ - m + 1;
  // The estimate of the regime just left: theta_hat before the change.
  theta_keep_ = m < count_ ? th_[static_cast<size_t>(at(m))] : *theta_hat;

  // Bank the regime just left when it lasted long enough for the estimate to settle.
  if (k_ - regime_start_k_ >= Ls_ && count_ > m) {
    Vec dir;
    double ysum = 0.0;
    const int len = std::min(Ld_, count_ - m);
    windowSums(m, len, &dir, &ysum);
    memory().remember(theta_keep_, dir / (len * dt_), rc_.merge_tolerance);
  }

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
    const int m = static_cast<int>(std::min<std::int64_t>(k_ - post_start_k_ + 1, count_));
    for (int j0 = m - 1; j0 >= 0; j0 -= Lc_) {
      const int len = std::min(Lc_, j0 + 1);
      addChunk(&Gr_, &hr_, &cr_, j0 - len + 1, len);
    }
    prior_ = *theta_hat;
    next_chunk_k_ = k_ + Lc_;
  }
}

void RobustPreadaptation::addChunk(Mat* G, Vec* h, double* c, int j0, int len) const {
  Vec Phi;
  double Y = 0.0;
  windowSums(j0, len, &Phi, &Y);
  G->noalias() += Phi * Phi.transpose();
  *h += Y * Phi;
  *c += Y * Y;
}

double RobustPreadaptation::chunkSigma() const {
  // The noise of a chunk sum is endpoint noise, the same as of a detection-window sum; a floor
  // of a tenth of the threshold keeps clean data from acting on round-off.
  return std::max(noiseLevel() * Ld_ * dt_, 0.1 * rc_.threshold * Lc_ * dt_);
}

bool RobustPreadaptation::refine(Vec* theta_hat) {
  if (!regime_fit_ || verifying_ || k_ < next_chunk_k_) return false;
  next_chunk_k_ += Lc_;
  addChunk(&Gr_, &hr_, &cr_, 0, Lc_);
  // Bayesian least squares of the regime's data around the prior (the decision's estimate):
  // excited directions follow the data, unexcited ones stay at the prior.
  const double sigma = chunkSigma();
  const int n = static_cast<int>(B_.size());
  Mat Gl = Gr_;
  const double lambda =
      sigma * sigma / (rc_.prior_std * rc_.prior_std) + rc_.ridge * std::max(Gr_.trace(), 0.0);
  for (int i = 0; i < n; ++i) Gl(i, i) += lambda;
  const Vec fit = prior_ + Gl.ldlt().solve(hr_ - Gr_ * prior_);
  const double step = std::min(1.0, rc_.cl_gain * Lc_ * dt_);
  Vec next = *theta_hat + step * (fit - *theta_hat);
  // Do no harm along the recent data: the pull may not make theta_hat explain the last long
  // window worse than it did, beyond noise. The regime's fit also carries the data since the
  // change and its prior; along the direction the plant shows now, the recent data is the
  // better judge (on a steady state a drift along it builds an error that rac would not have).
  const int len = static_cast<int>(std::min<std::int64_t>(
      {static_cast<std::int64_t>(Ll_), k_ - post_start_k_ + 1, static_cast<std::int64_t>(count_)}));
  if (len > 0) {
    Vec phi;
    double y = 0.0;
    if (len == Ll_ && count_ >= Ll_) {
      // The whole long window: its running sums (push()), not a fresh sum of Ll_ samples
      // every chunk (that sum was a sixth of pa_robust's instructions).
      phi = phi_long_;
      y = y_long_;
    } else {
      windowSums(0, len, &phi, &y);
    }
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
  // Post-change data in chunks: G = sum Phi Phi^T, h = sum Phi Y, c = sum Y^2, so that the
  // identification error of any theta is J = c - 2 theta^T h + theta^T G theta.
  const int m = static_cast<int>(std::min<std::int64_t>(k_ - post_start_k_ + 1, count_));
  Mat G = Mat::Zero(n, n);
  Vec h = Vec::Zero(n);
  double c = 0.0;
  int chunks = 0;
  for (int j0 = m - 1; j0 >= 0; j0 -= Lc_, ++chunks) {
    const int len = std::min(Lc_, j0 + 1);
    addChunk(&G, &h, &c, j0 - len + 1, len);
  }
  auto J = [&](const Vec& th) { return std::max(0.0, c - 2.0 * th.dot(h) + th.dot(G * th)); };
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
  RegimeMemory mem = memory();
  int candidates = 1;
  for (int i = 0; i < mem.size(); ++i, ++candidates) {
    const double ji = J(mem.at(i).theta);
    if (ji < j_best && beats(mem.at(i).theta, ji)) {
      j_best = ji;
      kind = Event::Decision::kMemory;
      chosen = i;
      base = mem.at(i).theta;
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
    }
  }
  // Fit what the data determines (Bayesian least squares around the chosen base): excited
  // directions follow the data, the others keep the base. Applied only when the gain is
  // beyond noise (chi-square with n degrees of freedom, `significance` per parameter).
  Mat Gr = G;
  const double lambda =
      sigma * sigma / (rc_.prior_std * rc_.prior_std) + rc_.ridge * std::max(G.trace(), 0.0);
  for (int i = 0; i < n; ++i) Gr(i, i) += lambda;
  Vec fitted = base + Gr.ldlt().solve(h - G * base);
  const double j_fit = J(fitted);
  // The fit moves the base only when the base's mean mismatch over all post-change data,
  // |sum Y - base^T sum Phi|, is beyond z standard deviations: the total's noise is endpoint
  // noise only (the sums telescope). So noise moves nothing, and a recalled regime that
  // explains the data is used as remembered.
  Vec phi_tot;
  double y_tot = 0.0;
  windowSums(0, m, &phi_tot, &y_tot);
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
  windowSums(0, std::min(Ld_, count_), &dir, &ysum);
  memory().remember(theta_hat, dir / (std::min(Ld_, count_) * dt_), rc_.merge_tolerance);
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
  return std::make_unique<RobustPreadaptation>(*m.cfg, *m.plant, m.net);
}

}  // namespace preadaptive_mrac
