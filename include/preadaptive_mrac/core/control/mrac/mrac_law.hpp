#pragma once
/// \file mrac_law.hpp
/// \brief The paper's MRAC law (eq. adaptivecontrol): u_ad = -theta_hat^T x + k0 r,
/// theta_hat_dot = gamma x e_v^T P B, forward Euler with the sampled x, optionally with the
/// smooth projection onto Omega = {|theta| <= theta_max}.

#include "preadaptive_mrac/core/control/adaptive_law.hpp"
#include "preadaptive_mrac/core/small_ops.hpp"

namespace preadaptive_mrac {

struct ModeContext;

/// \brief The MRAC law of the paper with the projection option (docs/spec.md "Adaptation").
class MracLaw final : public AdaptiveLaw {
 public:
  /// \brief PB = P B [-], theta_hat0 the initial estimate, dt [s]; gains from `cfg`.
  MracLaw(const ControllerParams& cfg, const Vec& PB);
  std::unique_ptr<AdaptiveLaw> clone() const override { return std::make_unique<MracLaw>(*this); }
  void reset() override;
  const Vec& estimate() const override { return theta_hat_; }
  Vec* mutableEstimate() override { return &theta_hat_; }
  void constrain() override;
  double command(const LawInput& in) const override {
    return -dotOf(theta_hat_, *in.x) + k0_ * in.r;
  }
  void advance(const LawInput& in, bool adapt) override {
    if (!adapt) return;
    scaledTo(gamma_ * dotOf(*in.ev, PB_), *in.x, &upd_);
    if (projection_) {
      advanceProjected();
    } else {
      addScaled(dt_, upd_, &theta_hat_);
    }
  }
  void setTunables(const ControllerParams& cfg) override;

 private:
  /// \brief The Euler step of upd_ projected onto Omega.
  void advanceProjected();
  /// \brief Smooth projection (Pomet-Praly) of the update direction y at theta.
  void project(const Vec& theta, Vec* y) const;
  Vec PB_, theta_hat0_, theta_hat_, upd_;
  double dt_, k0_, gamma_;
  bool projection_;
  double theta_max_, epsilon_;
};

/// \brief The registry's factory of MracLaw.
std::unique_ptr<AdaptiveLaw> makeMracLaw(const ModeContext& m);

}  // namespace preadaptive_mrac
