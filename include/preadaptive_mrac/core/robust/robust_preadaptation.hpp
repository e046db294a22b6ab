#pragma once
/// \file robust_preadaptation.hpp
/// \brief `pa_robust`: preadaptation that detects a switch from the identification residual,
/// predicts theta from a bounded memory of regimes (and the network), and verifies every
/// candidate against the measured data before it moves theta_hat (docs/research/robust.md).
///
/// Identification data, one pair per sample (integral form, no differentiation of x):
///   phi_k = dt (x_{k-1} + x_k) / 2,
///   y_k   = B^T [x_k - x_{k-1} - dt (A (x_{k-1} + x_k) / 2 + B u_{k-1} + B1r r_{k-1})] / B^T B,
/// so that y_k = theta^T phi_k up to O(dt^3) while theta is constant (eq. plant). The residual
/// of an estimate over a window is sum (y - theta_hat^T phi) / T [rad, input-equivalent].
///
/// A loss of elevator effectiveness (the plant applies Lambda u) makes the data read
/// y = theta^T phi + (Lambda - 1) u dt instead. A square-wave excitation on the command
/// (`excitation`) identifies nu = 1 - Lambda per regime (instrumental variables, the excitation
/// as the instrument, loss_estimate.hpp); a remembered regime carries its nu into its recall, the
/// fit and concurrent learning, which then aim at the loop's fixed point (docs/research/robust.md).
///
/// The parts: the data (identification_window.hpp, chunk_sums.hpp), the loss estimate
/// (loss_estimate.hpp), the remembered regimes (regime_memory.hpp), the detection
/// (switch_detection.hpp) and the decision (regime_decision.hpp), both pure functions; this class
/// keeps their state and schedules them: detection, the onset, the decisions while verifying,
/// and the regime's concurrent learning.

#include <cstdint>
#include <utility>
#include <vector>

#include "preadaptive_mrac/core/control/event.hpp"
#include "preadaptive_mrac/core/control/network.hpp"
#include "preadaptive_mrac/core/control/preadaptation.hpp"
#include "preadaptive_mrac/core/robust/chunk_sums.hpp"
#include "preadaptive_mrac/core/robust/identification_window.hpp"
#include "preadaptive_mrac/core/robust/loss_estimate.hpp"
#include "preadaptive_mrac/core/robust/regime_memory.hpp"
#include "preadaptive_mrac/core/robust/switch_detection.hpp"
#include "preadaptive_mrac/params/controller_params.hpp"
#include "preadaptive_mrac/params/robust_params.hpp"

namespace preadaptive_mrac {

class RobustPreadaptation : public PreadaptationStrategy {
 public:
  /// \brief `A`, `B`, `B1r` the controller's design model; `K` is the baseline gain
  /// (u_baseline = -K^T x).
  RobustPreadaptation(const ControllerParams& cfg, const RobustParams& robust,
                      const Eigen::MatrixXd& A, const Eigen::VectorXd& B,
                      const Eigen::VectorXd& B1r, const Vec& K, PreadaptNetwork* net);
  std::unique_ptr<PreadaptationStrategy> clone(PreadaptNetwork* net) const override {
    auto c = std::make_unique<RobustPreadaptation>(*this);
    c->net_ = net;
    return c;
  }
  bool constrainsEvents() const override { return true; }
  bool keepsAtRecovery() const override { return true; }
  void reset() override;
  Detection detect(const Sample& s, const Vec& theta_hat, Attention* attention) override;
  void onOnset(const Sample& s, Vec* theta_hat, Event* ev) override;
  void onDecision(const Sample& s, Vec* theta_hat, Event* ev) override;
  void duringPhase(const Sample& s, double u, const Vec& theta_hat) override;
  void onRecovery(const Sample& s, const Vec& theta_hat, Event* ev) override;
  double phaseCost() const override { return phase_cost_; }
  bool refine(Vec* theta_hat) override;
  /// \brief Gains and thresholds take effect at once; a new detect_window, chunk or verify_time
  /// re-sizes the data window and restarts identification (returns true), as a reset does.
  bool setTunables(const ControllerParams& cfg, const RobustParams& robust) override;
  /// \brief The square wave +-`excitation` of period `excitation_period` at time t [rad]; with
  /// `excitation_time` > 0 only for that long after the last onset, else 0.
  double excitation(double t) const override;
  /// \brief `error_feedback`: the gain of -k e^T P B on the adaptive term.
  bool hasErrorFeedback() const override { return robust_.error_feedback != 0.0; }
  /// With `feedback_time` > 0, only that long after the last onset on s itself; in the steady
  /// flight after, on s low-passed with the time constant `steady_filter`.
  double errorFeedback(double t, double s) override;

  /// \brief The loss of effectiveness nu = 1 - Lambda identified over the current regime so far
  /// and its information (1 / variance); (0, 0) before enough data.
  std::pair<double, double> lossFit() const;
  /// \brief Mean residual of theta_hat over the last detection window [rad].
  double residual() const { return residual_; }
  /// \brief Current trigger threshold max(threshold, noise_factor * noise) [rad].
  double triggerThreshold() const;
  /// \brief Estimated standard deviation of the residual from noise alone [rad].
  double noiseLevel() const { return noise_.level(); }

 private:
  /// \brief For n = 3: phi = dt x_mid and the input-equivalent residual d of the last step.
  void residualSample3(const Vec& x, double u_prev, double r_prev, Vec* phi, Vec* d) const;
  /// \brief Store the identification pair of the step that ends at sample `s` (with the
  /// estimate it was flown with) and its loss-fit sample.
  void addSample(const Sample& s, const Vec& theta_hat);
  /// \brief The detection's settings from robust_ and the window lengths.
  DetectionSettings detectionSettings() const;
  /// \brief Gather the post-change data and the candidates, decide (regime_decision.hpp) and
  /// apply the result.
  void decide(Vec* theta_hat, Event* ev);
  /// \brief Add the chunk sums of the `m` newest samples, oldest chunk first; returns the
  /// number of chunks.
  int addChunks(ChunkSums* sums, int m, bool with_loss) const;
  /// \brief The loss a remembered entry carries into its recall: 0 unless `significance`
  /// from 0.
  double entryLoss(const RegimeEntry& e) const;
  /// \brief Half-period of the excitation that time t falls in.
  std::int64_t excitationHalf(double t) const;
  /// \brief The residual y - th^T phi of summed data under the model in force: with the
  /// regime's loss nu the plant applies 1 - nu of each command, so the data reads
  /// y = (1 - nu) th^T phi + nu v (v the sum of the loss regressor).
  double residualOf(const Vec& theta_hat, const Vec& phi, double y, double v) const;
  /// \brief The sum of v over `len` samples from j0 ago, read only under a loss (else 0).
  double lossV(int j0, int len) const;
  /// \brief Noise standard deviation of one chunk sum [rad s].
  double chunkSigma() const;
  RegimeMemory memory();
  /// Window lengths in samples and the ring's capacity from robust_.
  void sizeWindows();

  RobustParams robust_;
  Vec K_;
  bool projection_;
  double theta_max_, dt_;
  Mat A_;
  Vec B_, B1r_;
  double b_norm2_;  ///< B^T B
  PreadaptNetwork* net_;
  // controller.robust's times in samples: detect_window, chunk, verify_time, quiet_time,
  // settle_time, long_window (0: none), min_dwell; and the ring's capacity.
  int detect_samples_ = 1, chunk_samples_ = 1, verify_samples_ = 1, quiet_samples_ = 1;
  int settle_samples_ = 1, long_samples_ = 0, dwell_samples_ = 0, ring_capacity_ = 0;
  IdentificationWindow window_;     // the data: ring and long-window sums
  double long_residual_ = 0.0;      ///< over the long window when it was last due [rad]
  bool long_trigger_ = false;       ///< the last onset came from the long window
  std::vector<double> cumulative_;  ///< the onset's cumulative residual (ring_capacity_ long)
  std::int64_t k_ = 0;
  bool have_prev_ = false;
  Vec x_prev_;
  // Detection.
  double residual_ = 0.0;  ///< over the last detection window [rad]
  NoiseEstimate noise_;
  std::int64_t last_trigger_k_ = -1000000000;
  // Phase.
  bool verifying_ = false;
  bool first_move_ = false;  ///< no decision since the onset has moved theta_hat yet
  std::int64_t post_start_k_ = 0, verify_end_k_ = 0, next_decision_k_ = 0, regime_start_k_ = 0;
  int quiet_count_ = 0;
  Vec theta_keep_, theta_net_;
  NetInput z_onset_ = NetInput::Zero();
  // The regime since the last decision: its chunk sums (with the loss regressor's) and the
  // prior of the concurrent-learning fit, and the loss its fit aims with (the recalled
  // entry's).
  bool regime_fit_ = false;
  ChunkSums regime_;
  Vec prior_;
  std::int64_t next_chunk_k_ = 0;
  double nu_regime_ = 0.0, nu_decided_ = 0.0;
  double forget_ = 1.0;  ///< per chunk, from forget_time (1: no forgetting)
  LossEstimate loss_;
  double t_prev_ = 0.0;
  double excite_until_ = 0.0;    ///< the excitation runs before this time (excitation_time > 0)
  double feedback_until_ = 0.0;  ///< the error feedback acts on s itself before this time
  double s_slow_ = 0.0;          ///< e^T P B low-passed (steady_filter)
  int recalled_ = -1;
  double phase_cost_ = 0.0;
};

struct ModeContext;
/// \brief The registry's factory (mode_registry.hpp).
std::unique_ptr<PreadaptationStrategy> makeRobustPreadaptation(const ModeContext& m);

}  // namespace preadaptive_mrac
