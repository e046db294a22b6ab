#pragma once
/// \file adaptive_law.hpp
/// \brief The adaptive-law seam: what the controller asks of an adaptive law (MRAC today,
/// mrac/mrac_law.hpp). A law owns its estimate theta_hat, its control term u_ad and its update.
///
/// Adding a law (docs/design.md, "A new adaptive law"): a folder core/control/<law>/ with a
/// class implementing AdaptiveLaw, its factory `std::unique_ptr<AdaptiveLaw>
/// make<Law>Law(const ModeContext&)` and, in its .cpp, the line that registers it by name
/// (registerLaw, controller/mode_registry.hpp); a mode names it in params/modes.yaml.
/// The controller keeps the baseline -K x, the reference model, the velocity estimator, the
/// attention and the actuator limits; the law sees x_k, e_v = x_k - x_r and r_k.

#include <memory>

#include "preadaptive_mrac/core/types.hpp"

namespace preadaptive_mrac {

struct ControllerParams;

/// \brief What a law sees of one sample t_k.
struct LawInput {
  const Vec* x = nullptr;   ///< measured state x_k
  const Vec* ev = nullptr;  ///< e_v = x_k - x_r(t_k)
  double r = 0.0;           ///< command r(t_k) [rad]
  /// What the known actuator limits took off the command at t_k, u_limited - u [rad], when the
  /// controller hedges (controller.adaptation.hedging); 0 otherwise. A law that predicts the
  /// plant feeds its prediction the limited command.
  double limited = 0.0;
};

/// \brief An adaptive law: u = u_bl + command(), then advance() to t_{k+1}.
class AdaptiveLaw {
 public:
  virtual ~AdaptiveLaw() = default;
  /// \brief A copy with the same state (Controller's copy).
  virtual std::unique_ptr<AdaptiveLaw> clone() const = 0;
  /// \brief Back to the initial estimate and state.
  virtual void reset() = 0;
  /// \brief The estimate theta_hat used for the command at this sample.
  virtual const Vec& estimate() const = 0;
  /// \brief The estimate for a strategy to overwrite (a preadaptation reset, a refinement); the
  /// controller calls constrain() after such a change when the strategy asks for it.
  virtual Vec* mutableEstimate() = 0;
  /// \brief Bring an estimate changed from outside back into the law's admissible set (the
  /// projection's ball when projection is on). Default: nothing to keep.
  virtual void constrain() {}
  /// \brief The adaptive control term u_ad [rad] at this sample.
  virtual double command(const LawInput& in) const = 0;
  /// \brief Advance the estimate (and any state of the law) to t_{k+1}; `adapt` false freezes
  /// the estimate over this sample (the elevator was at a limit).
  virtual void advance(const LawInput& in, bool adapt) = 0;
  /// \brief New tunables between two samples; `cfg` is the whole configuration with them.
  virtual void setTunables(const ControllerParams& cfg) { (void)cfg; }
};

}  // namespace preadaptive_mrac
