#include "preadaptive_mrac/core/robust/robust_preadaptation.hpp"

#include <algorithm>
#include <cmath>

#include "preadaptive_mrac/core/control/attention.hpp"
#include "preadaptive_mrac/core/control/design_model.hpp"
#include "preadaptive_mrac/core/control/mode_context.hpp"
#include "preadaptive_mrac/core/robust/regime_decision.hpp"
#include "preadaptive_mrac/core/robust/switch_detection.hpp"
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
    : robust_(robust),
      K_(K),
      projection_(cfg.projection),
      theta_max_(cfg.theta_max),
      dt_(cfg.sample_time),
      A_(A),
      B_(B),
      B1r_(B1r),
      b_norm2_(B.squaredNorm()),
      net_(net),
      loss_(static_cast<int>(B.size())) {
  sizeWindows();
  const int n = static_cast<int>(B.size());
  window_.resize(ring_capacity_, long_samples_, n);
  x_prev_.setZero(n);
  theta_keep_.setZero(n);
  theta_net_.setZero(n);
  regime_.clear(n);
  prior_.setZero(n);
  net_->state().regimes.reserve(static_cast<size_t>(std::max(robust_.memory_size, 0)) + 1);
  reset();
}

void RobustPreadaptation::sizeWindows() {
  detect_samples_ = samplesOf(robust_.detect_window, dt_);
  chunk_samples_ = samplesOf(robust_.chunk, dt_);
  verify_samples_ = samplesOf(robust_.verify_time, dt_);
  quiet_samples_ = samplesOf(robust_.quiet_time, dt_);
  settle_samples_ = samplesOf(robust_.settle_time, dt_);
  dwell_samples_ = samplesOf(robust_.min_dwell, dt_);
  long_samples_ = robust_.long_window > 0.0
                      ? std::max(detect_samples_, samplesOf(robust_.long_window, dt_))
                      : 0;
  // Each chunk's weight on the regime's fit falls by this factor per chunk after it.
  forget_ = robust_.forget_time > 0.0 ? std::exp(-chunk_samples_ * dt_ / robust_.forget_time) : 1.0;
  ring_capacity_ =
      std::max({2 * detect_samples_, verify_samples_ + 2 * detect_samples_, 2 * long_samples_}) + 2;
  cumulative_.assign(static_cast<size_t>(ring_capacity_), 0.0);
}

bool RobustPreadaptation::setTunables(const ControllerParams& cfg, const RobustParams& robust) {
  const int ld = detect_samples_, lc = chunk_samples_, lv = verify_samples_, ll = long_samples_;
  robust_ = robust;
  projection_ = cfg.projection;
  theta_max_ = cfg.theta_max;
  sizeWindows();
  net_->state().regimes.reserve(static_cast<size_t>(std::max(robust_.memory_size, 0)) + 1);
  const int before = memory().size();
  memory().trim();
  if (memory().size() != before) recalled_ = -1;  // indices moved
  if (detect_samples_ == ld && chunk_samples_ == lc && verify_samples_ == lv && long_samples_ == ll)
    return false;
  // The ring's sums and the detection statistics are per window: start them again.
  window_.resize(ring_capacity_, long_samples_, B_.size());
  reset();
  return true;
}

void RobustPreadaptation::reset() {
  window_.clear();
  k_ = 0;
  have_prev_ = false;
  residual_ = 0.0;
  noise_ = NoiseEstimate();
  last_trigger_k_ = -1000000000;
  verifying_ = false;
  post_start_k_ = verify_end_k_ = next_decision_k_ = regime_start_k_ = 0;
  quiet_count_ = 0;
  recalled_ = -1;
  phase_cost_ = 0.0;
  regime_fit_ = false;
  regime_.c = 0.0;
  next_chunk_k_ = 0;
  long_residual_ = 0.0;
  long_trigger_ = false;
  nu_regime_ = nu_decided_ = 0.0;
  loss_.restart(-1);
  loss_.clearBlock();
  t_prev_ = 0.0;
  // The regime flown from the start is identified as one after an onset.
  excite_until_ = robust_.excitation_time;
  feedback_until_ = robust_.feedback_time;
  s_slow_ = 0.0;
}

RegimeMemory RobustPreadaptation::memory() {
  return RegimeMemory(&net_->state().regimes, robust_.memory_size);
}

// phi = dt x_mid and d = x_k - x_{k-1} - dt (A x_mid + B u + B1r r) for three states, with the
// bits of the generic branch of detect(): Eigen forms A x_mid as a matrix-vector product whose
// every row is summed from column 0 up, and adds the input terms after it, left to right.
void RobustPreadaptation::residualSample3(const Vec& x, double u_prev, double r_prev, Vec* phi,
                                          Vec* d) const {
  const double xm[3] = {0.5 * (x_prev_[0] + x[0]), 0.5 * (x_prev_[1] + x[1]),
                        0.5 * (x_prev_[2] + x[2])};
  phi->resize(3);
  d->resize(3);
  for (int i = 0; i < 3; ++i) {
    const double ax = (A_(i, 0) * xm[0] + A_(i, 1) * xm[1]) + A_(i, 2) * xm[2];
    (*d)[i] = (x[i] - x_prev_[i]) - dt_ * ((ax + B_[i] * u_prev) + B1r_[i] * r_prev);
    (*phi)[i] = dt_ * xm[i];
  }
}

DetectionSettings RobustPreadaptation::detectionSettings() const {
  DetectionSettings set;
  set.threshold = robust_.threshold;
  set.noise_factor = robust_.noise_factor;
  set.window_time = detect_samples_ * dt_;
  set.noise_time = robust_.noise_time;
  set.detect_window = detect_samples_;
  set.long_window = long_samples_;
  set.min_dwell = dwell_samples_;
  set.quiet = quiet_samples_;
  return set;
}

double RobustPreadaptation::residualOf(const Vec& theta_hat, const Vec& phi, double y,
                                       double v) const {
  const double predicted = dotOf(theta_hat, phi);
  const double r = y - predicted;
  // A regime recalled with its loss: what the plant did not apply of the error feedback, the
  // probing and the rest of the command is the model in force, not a mismatch to detect.
  return nu_regime_ > 0.0 ? r - nu_regime_ * (v - predicted) : r;
}

double RobustPreadaptation::lossV(int j0, int len) const {
  return nu_regime_ > 0.0 ? window_.vSum(j0, len) : 0.0;
}

double RobustPreadaptation::triggerThreshold() const {
  return shortThreshold(detectionSettings(), noiseLevel());
}

void RobustPreadaptation::addSample(const Sample& s, const Vec& theta_hat) {
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
    y_k = dotOf(B_, d) / b_norm2_;
    v_k = -s.u_prev * dt_ - K_.dot(phi_k);
    window_.push(phi_k, y_k, theta_hat, v_k);
  }
  copyTo(x, &x_prev_);
  have_prev_ = true;
  ++k_;
  // The loss fit's sample covers [t_prev, t_k]: the command there carried excitation(t_prev).
  if (sample && robust_.excitation > 0.0 && robust_.loss_max > 0.0)
    loss_.add(k_, excitationHalf(t_prev_), phi_k, y_k, v_k, excitation(t_prev_) * dt_);
  t_prev_ = s.t;
}

Detection RobustPreadaptation::detect(const Sample& s, const Vec& theta_hat, Attention* attention) {
  addSample(s, theta_hat);
  if (window_.count() < detect_samples_) return Detection::kNone;

  const double window_time = detect_samples_ * dt_;
  Vec phi;
  double y = 0.0;
  window_.sums(0, detect_samples_, &phi, &y);
  Residuals rho;
  rho.detect = residual_ = residualOf(theta_hat, phi, y, lossV(0, detect_samples_)) / window_time;
  const DetectionSettings set = detectionSettings();
  DetectionClock clock;
  clock.since_onset = k_ - last_trigger_k_;
  clock.since_verified = k_ - verify_end_k_;
  clock.stored = window_.count();
  clock.noise_due = k_ % detect_samples_ == 0 && window_.count() >= 2 * detect_samples_;
  clock.verifying = verifying_;
  clock.decision_due = k_ >= next_decision_k_;
  clock.phase_active = attention->phaseActive();
  // The window before and the long window: summed only when they are read.
  if (clock.noise_due && !verifying_) {
    window_.sums(detect_samples_, detect_samples_, &phi, &y);
    rho.previous =
        residualOf(theta_hat, phi, y, lossV(detect_samples_, detect_samples_)) / window_time;
  }
  if (longWindowDue(set, clock)) {
    long_residual_ = residualOf(theta_hat, window_.phiLong(), window_.yLong(), window_.vLong()) /
                     (long_samples_ * dt_);
    rho.long_window = long_residual_;
  }
  const DetectionResult det = detectSwitch(rho, noise_, clock, quiet_count_, set);
  noise_ = det.noise;
  if (det.kind == Detection::kOnset) long_trigger_ = det.long_trigger;
  quiet_count_ = det.quiet;
  return det.kind;
}

void RobustPreadaptation::onOnset(const Sample& s, Vec* theta_hat, Event* ev) {
  // Where did the mismatch begin? The cumulative residual from the newest sample back grows
  // while the data is post-change and hardly before (change_point: the kink of its
  // least-squares fit, or the shortest span holding 90 % of its largest excursion).
  const int span =
      long_trigger_
          ? static_cast<int>(std::min<std::int64_t>({static_cast<std::int64_t>(window_.count()),
                                                     2 * long_samples_, k_ - verify_end_k_}))
          : std::min(window_.count(), std::max(2 * detect_samples_, 2));
  const double rho = long_trigger_ ? long_residual_ : residual_;
  const double sgn = rho >= 0.0 ? 1.0 : -1.0;
  double S = 0.0;
  for (int j = 0; j < span; ++j) {
    const int i = window_.at(j);
    S += sgn * residualOf(*theta_hat, window_.phi(i), window_.y(i), window_.v(i));
    cumulative_[static_cast<size_t>(j)] = S;
  }
  // The noise of one sum about its mean is one endpoint's: chunkSigma() is two endpoints'.
  const double endpoint = chunkSigma() / std::sqrt(2.0);
  const int m =
      robust_.change_point == ChangePoint::kFit
          ? kinkChangePoint(cumulative_.data(), span, robust_.significance * endpoint * endpoint)
          : excursionChangePoint(cumulative_.data(), span);
  post_start_k_ = k_ - m + 1;
  // The estimate of the regime just left: theta_hat before the change.
  theta_keep_ = m < window_.count() ? window_.theta(window_.at(m)) : *theta_hat;

  // Bank the regime just left when it lasted long enough for the estimate to settle.
  if (k_ - regime_start_k_ >= settle_samples_ && window_.count() > m) {
    Vec dir;
    double ysum = 0.0;
    const int len = std::min(detect_samples_, window_.count() - m);
    window_.sums(m, len, &dir, &ysum);
    // With the loss of effectiveness fitted over the visit (pooled with the entry's).
    const std::pair<double, double> loss = lossFit();
    memory().remember(theta_keep_, dir / (len * dt_), robust_.merge_tolerance, loss.first,
                      loss.second);
  }
  loss_.restart(-1);

  // Probe the elevator while this regime is identified, not in the steady flight after it.
  // An onset while the probe runs ends it: either the regime is still changing (no clean loss
  // fit) or the probe itself shows in the residual as a switch (an elevator far more or less
  // effective than the model's), and a probe that each onset renewed would run for good.
  if (robust_.excitation_time > 0.0)
    excite_until_ = s.t < excite_until_ ? s.t : s.t + robust_.excitation_time;
  if (robust_.feedback_time > 0.0) feedback_until_ = s.t + robust_.feedback_time;
  z_onset_ << s.e, std::abs(s.e_dot);
  if (robust_.use_network) net_->forward(z_onset_, &theta_net_);
  last_trigger_k_ = k_;
  regime_fit_ = false;
  verifying_ = true;
  first_move_ = true;
  verify_end_k_ = k_ + verify_samples_;
  next_decision_k_ = k_ + chunk_samples_;
  quiet_count_ = 0;
  recalled_ = -1;
  phase_cost_ = 0.0;
  if (m >= chunk_samples_) {
    decide(theta_hat, ev);
  } else {  // too little post-change data to decide on: the first decision comes with a chunk
    next_decision_k_ = post_start_k_ + chunk_samples_ - 1;
  }
}

void RobustPreadaptation::onDecision(const Sample& s, Vec* theta_hat, Event* ev) {
  (void)s;
  decide(theta_hat, ev);
  next_decision_k_ += chunk_samples_;
  if (k_ >= verify_end_k_) {
    verifying_ = false;
    quiet_count_ = 0;
    regime_start_k_ = post_start_k_;
    if (recalled_ >= 0) memory().markUsed(recalled_);
    // Concurrent learning from here on: the regime's data so far, then every new chunk.
    regime_fit_ = robust_.cl_gain > 0.0;
    regime_.clear(B_.size());
    const int m = static_cast<int>(std::min<std::int64_t>(k_ - post_start_k_ + 1, window_.count()));
    addChunks(&regime_, m, true);
    // The regime's fit aims with the loss the last decision used (a recalled entry's).
    nu_regime_ = nu_decided_;
    loss_.restart(k_);
    prior_ = *theta_hat;
    next_chunk_k_ = k_ + chunk_samples_;
  }
}

int RobustPreadaptation::addChunks(ChunkSums* sums, int m, bool with_loss) const {
  int chunks = 0;
  for (int j0 = m - 1; j0 >= 0; j0 -= chunk_samples_, ++chunks) {
    const int len = std::min(chunk_samples_, j0 + 1);
    sums->add(window_, j0 - len + 1, len, with_loss);
  }
  return chunks;
}

double RobustPreadaptation::chunkSigma() const {
  // The noise of a chunk sum is endpoint noise, the same as of a detection-window sum; a floor
  // of a tenth of the threshold keeps clean data from acting on round-off.
  return std::max(noiseLevel() * detect_samples_ * dt_,
                  0.1 * robust_.threshold * chunk_samples_ * dt_);
}

bool RobustPreadaptation::refine(Vec* theta_hat) {
  if (!regime_fit_ || verifying_ || k_ < next_chunk_k_) return false;
  next_chunk_k_ += chunk_samples_;
  // With a loss nu the data reads y = (1 - nu) th^T phi + nu (theta_rec^T phi + ...) for the
  // loop's fixed point th: the fit aims at th through (Y - nu v) / (1 - nu).
  const double nu = nu_regime_;
  // The recent data: the last long window (or what the regime has of it so far).
  const int len = static_cast<int>(
      std::min<std::int64_t>({static_cast<std::int64_t>(long_samples_), k_ - post_start_k_ + 1,
                              static_cast<std::int64_t>(window_.count())}));
  Vec phi;
  double y = 0.0;
  if (len > 0) {
    if (len == long_samples_ && window_.count() >= long_samples_) {
      // The whole long window: its running sums (push()), not a fresh sum of long_samples_
      // samples every chunk (that sum would be a sixth of pa_robust's instructions).
      phi = window_.phiLong();
      y = window_.yLong();
    } else {
      window_.sums(0, len, &phi, &y);
    }
    if (nu > 0.0) y = (y - nu * window_.vSum(0, len)) / (1.0 - nu);
  }
  const double significant = std::sqrt(robust_.significance) * chunkSigma();
  const double r0 = len > 0 ? y - theta_hat->dot(phi) : 0.0;
  // A regime that drifts (the trim moving with the airspeed): while the recent data disagrees
  // with the estimate beyond noise, older chunks weigh less, so the estimate follows instead
  // of the drift being detected again and again as a switch. A steady regime keeps them all.
  if (robust_.forget_time > 0.0 && std::abs(r0) > significant) regime_.scale(forget_);
  regime_.add(window_, 0, chunk_samples_, nu > 0.0);
  // Bayesian least squares of the regime's data around the prior (the decision's estimate):
  // excited directions follow the data, unexcited ones stay at the prior.
  const Vec fit = ridgeFit(regime_.G, regime_.hFixed(nu), prior_, chunkSigma(), robust_.prior_std,
                           robust_.ridge);
  const double step = std::min(1.0, robust_.cl_gain * chunk_samples_ * dt_);
  Vec next = *theta_hat + step * (fit - *theta_hat);
  // Do no harm along the recent data: the pull may not make theta_hat explain the last long
  // window worse than it did, beyond noise. The regime's fit also carries the data since the
  // change and its prior; along the direction the plant shows now, the recent data is the
  // better judge (on a steady state a drift along it builds an error that rac would not have).
  const double pp = len > 0 ? phi.squaredNorm() : 0.0;
  if (pp > 0.0) {
    const double r1 = y - next.dot(phi);
    const double allowed = std::max(std::abs(r0), significant);
    if (std::abs(r1) > allowed) next += phi * ((r1 - (r1 > 0.0 ? allowed : -allowed)) / pp);
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
  cand.use_network = robust_.use_network;
  if (cand.use_network) cand.network = theta_net_;
  // Post-change data in chunks, and its plain sums.
  const int m = static_cast<int>(std::min<std::int64_t>(k_ - post_start_k_ + 1, window_.count()));
  DecisionData data;
  data.chunks.clear(B_.size());
  const int chunks = addChunks(&data.chunks, m, any_loss);
  window_.sums(0, m, &data.phi_tot, &data.y_tot);
  DecisionSettings set;
  set.sigma = chunkSigma();
  set.z = std::sqrt(robust_.significance);  // in standard deviations
  set.margin = robust_.margin;
  set.prior_std = robust_.prior_std;
  set.ridge = robust_.ridge;
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
  const double Tc = chunk_samples_ * dt_;
  const double norm = 1.0 / (std::sqrt(static_cast<double>(std::max(chunks, 1))) * Tc);
  ev->score =
      std::sqrt(kind == Event::Decision::kKeep ? res.error_keep : data.chunks.error(*theta_hat)) *
      norm;
  ev->score_keep = std::sqrt(res.error_keep) * norm;
}

double RobustPreadaptation::entryLoss(const RegimeEntry& e) const {
  // Only a loss `significance` (3 sigma) from 0; an elevator more effective than modelled
  // (nu < 0) is not used.
  if (robust_.loss_max <= 0.0 || !(e.loss_info > 0.0)) return 0.0;
  if (!(e.loss * std::sqrt(e.loss_info) > std::sqrt(robust_.significance))) return 0.0;
  return std::min(e.loss, robust_.loss_max);
}

std::int64_t RobustPreadaptation::excitationHalf(double t) const {
  return static_cast<std::int64_t>(std::floor(2.0 * t / robust_.excitation_period + 1e-9));
}

double RobustPreadaptation::errorFeedback(double t, double s) {
  if (robust_.feedback_time <= 0.0) return robust_.error_feedback * s;
  // In the transient a switch leaves, the feedback acts on the error as it is (the faster it
  // acts, the sooner the error returns). In steady flight the measured error is mostly sensor
  // noise, white at the sample rate, while what a quiet switch leaves is slow: the feedback
  // then acts on the low-passed error, and the elevator does not answer the noise.
  s_slow_ += dt_ / (robust_.steady_filter + dt_) * (s - s_slow_);
  return robust_.error_feedback * (t < feedback_until_ ? s : s_slow_);
}

double RobustPreadaptation::excitation(double t) const {
  if (robust_.excitation <= 0.0) return 0.0;
  if (robust_.excitation_time > 0.0 && !(t < excite_until_)) return 0.0;
  return excitationHalf(t) % 2 == 0 ? robust_.excitation : -robust_.excitation;
}

std::pair<double, double> RobustPreadaptation::lossFit() const {
  if (robust_.loss_max <= 0.0 || robust_.excitation <= 0.0) return {0.0, 0.0};
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
  window_.sums(0, std::min(detect_samples_, window_.count()), &dir, &ysum);
  memory().remember(theta_hat, dir / (std::min(detect_samples_, window_.count()) * dt_),
                    robust_.merge_tolerance);
  if (robust_.use_network && robust_.network_rate > 0.0) {
    // Supervised: move the network's prediction at this onset's input towards the regime's
    // settled estimate (E = |theta_I - theta_hat|^2 / 2, so dE/dtheta_I = theta_I - theta_hat).
    Vec pred;
    net_->forward(z_onset_, &pred);
    ev->grad = pred - theta_hat;
    net_->learn(z_onset_, ev->grad, robust_.network_rate);
    ev->learned = true;
  }
}

std::unique_ptr<PreadaptationStrategy> makeRobustPreadaptation(const ModeContext& m) {
  return std::make_unique<RobustPreadaptation>(*m.cfg, *m.robust, m.model->A, *m.B, m.model->B1r,
                                               Vec(m.design->K.transpose()), m.net);
}

}  // namespace preadaptive_mrac
