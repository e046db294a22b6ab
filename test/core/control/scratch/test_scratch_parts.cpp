// docs/design.md's recipes for a new law and a new strategy, followed once: a scratch law (MRAC
// with a dead zone: no adaptation while |e| <= attention.c_e) and a scratch strategy
// (theta_hat := 0 at each onset), each written here as its folder would hold it and registered
// in one line, each with a mode of registered parts, run in the batch closed loop on the paper's
// scenario 1. The file is found by cmake/tests.cmake (test/core/control/*/test_*.cpp): no
// build list names it.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <string>

#include "preadaptive_mrac/core/control/adaptive_law.hpp"
#include "preadaptive_mrac/core/control/design_model.hpp"
#include "preadaptive_mrac/core/control/event.hpp"
#include "preadaptive_mrac/core/control/mode_context.hpp"
#include "preadaptive_mrac/core/control/part_registry.hpp"
#include "preadaptive_mrac/core/control/preadaptation.hpp"
#include "preadaptive_mrac/core/controller/mode_registry.hpp"
#include "preadaptive_mrac/core/small_ops.hpp"
#include "preadaptive_mrac/params/controller_params.hpp"
#include "preadaptive_mrac/params/modes_params.hpp"
#include "test_helpers.hpp"

namespace preadaptive_mrac {
namespace {

// ---- what core/control/deadzone/deadzone_law.{hpp,cpp} would hold ----

/// The paper's MRAC update (forward Euler, no projection), frozen while |e| <= c_e.
class DeadzoneLaw final : public AdaptiveLaw {
 public:
  DeadzoneLaw(const ControllerParams& cfg, const Vec& PB, int out)
      : PB_(PB),
        theta_hat0_(cfg.theta_hat0),
        dt_(cfg.sample_time),
        k0_(cfg.k0),
        gamma_(cfg.gamma),
        zone_(cfg.c_e),
        out_(out) {
    reset();
  }
  std::unique_ptr<AdaptiveLaw> clone() const override {
    return std::make_unique<DeadzoneLaw>(*this);
  }
  void reset() override { theta_hat_ = theta_hat0_; }
  const Vec& estimate() const override { return theta_hat_; }
  Vec* mutableEstimate() override { return &theta_hat_; }
  double command(const LawInput& in) const override {
    return -dotOf(theta_hat_, *in.x) + k0_ * in.r;
  }
  void advance(const LawInput& in, bool adapt) override {
    if (!adapt || std::abs((*in.ev)[out_]) <= zone_) return;
    theta_hat_ += (dt_ * gamma_ * dotOf(*in.ev, PB_)) * *in.x;
  }

 private:
  Vec PB_, theta_hat0_, theta_hat_;
  double dt_, k0_, gamma_, zone_;
  int out_;
};

std::unique_ptr<AdaptiveLaw> makeDeadzoneLaw(const ModeContext& m) {
  return std::make_unique<DeadzoneLaw>(*m.cfg, *m.PB, m.model->output_index);
}

// The recipe's registration line.
const bool kDeadzoneRegistered = registerLaw("deadzone", makeDeadzoneLaw);

// ---- what core/control/zero/zero_preadaptation.{hpp,cpp} would hold ----

/// theta_hat := 0 at each onset of the attention function (the interface's default detect).
class ZeroPreadaptation final : public PreadaptationStrategy {
 public:
  std::unique_ptr<PreadaptationStrategy> clone(PreadaptNetwork* net) const override {
    (void)net;
    return std::make_unique<ZeroPreadaptation>(*this);
  }
  void onOnset(const Sample& s, Vec* theta_hat, Event* ev) override {
    (void)s;
    theta_hat->setZero();
    ev->reset = true;
  }
  void duringPhase(const Sample& s, double u, const Vec& theta_hat) override {
    (void)s;
    (void)u;
    (void)theta_hat;
  }
  void onRecovery(const Sample& s, const Vec& theta_hat, Event* ev) override {
    (void)s;
    (void)theta_hat;
    (void)ev;
  }
};

std::unique_ptr<PreadaptationStrategy> makeZeroPreadaptation(const ModeContext& m) {
  (void)m;
  return std::make_unique<ZeroPreadaptation>();
}

const bool kZeroRegistered = registerStrategy("zero", makeZeroPreadaptation);

// ---- the modes: here registered by the test; a mode users see is a row of params/modes.yaml ----

const bool kModesRegistered =
    registerMode("rac_deadzone", "MRAC frozen while |e| <= c_e, theta_hat never reset", "deadzone",
                 "paper_rac", false) &&
    registerMode("pa_zero", "MRAC, theta_hat := 0 at each onset", "mrac", "zero", false);

// Scenario 1 in `mode`; `every_switch`: the attention's rate threshold low enough to see each
// of its switches (as test_closed_loop's learning runs).
SimResult run(const std::string& mode, bool every_switch = false) {
  RunConfig cfg = test::packageConfig("1");
  cfg.controller.mode = mode;
  if (every_switch) cfg.controller.c_ed = 0.015;
  return test::simulate(cfg);
}

TEST(ScratchParts, RegisteredModesComeAfterTheTablesAndBuildTheirParts) {
  ASSERT_TRUE(kDeadzoneRegistered && kZeroRegistered && kModesRegistered);
  const auto& modes = modeRegistry();
  const std::size_t n = std::size(params::kModeRows);
  ASSERT_EQ(modes.size(), n + 2);
  for (std::size_t i = 0; i < n; ++i) EXPECT_STREQ(modes[i].name, params::kModeRows[i].name);
  EXPECT_STREQ(modes[n].name, "rac_deadzone");
  EXPECT_STREQ(modes[n + 1].name, "pa_zero");
  EXPECT_EQ(findMode("rac_deadzone"), &modes[n]);
  EXPECT_NE(modeNames(", ").find("rac_deadzone, pa_zero"), std::string::npos);
  for (const char* name : {"rac_deadzone", "pa_zero"}) {
    RunConfig cfg = test::packageConfig("1");
    cfg.controller.mode = name;
    const Controller ctl(designModelOf(cfg.plant, cfg.controller), cfg.controller);
    EXPECT_EQ(ctl.mode(), name);
    EXPECT_EQ(ctl.needsTruth(), findMode(name)->truth) << name;
  }
}

// Only the dead zone freezes theta_hat at small |e|: rac moves it there.
TEST(ScratchParts, TheDeadzoneLawFreezesThetaHatWhileTheErrorIsSmall) {
  const double c_e = test::packageConfig("1").controller.c_e;
  const Series dz = run("rac_deadzone").series;
  const Series rac = run("rac").series;
  ASSERT_EQ(dz.t.size(), rac.t.size());
  int frozen = 0, moved = 0, rac_moved_small = 0;
  for (std::size_t k = 0; k + 1 < dz.t.size(); ++k) {
    if (std::abs(dz.e[k]) <= c_e) {
      ASSERT_EQ(dz.theta_hat[k + 1], dz.theta_hat[k]) << "t = " << dz.t[k];
      ++frozen;
    } else if (dz.theta_hat[k + 1] != dz.theta_hat[k]) {
      ++moved;
    }
    if (std::abs(rac.e[k]) <= c_e && rac.theta_hat[k + 1] != rac.theta_hat[k]) ++rac_moved_small;
  }
  EXPECT_GT(frozen, 1000);
  EXPECT_GT(moved, 1000);
  EXPECT_GT(rac_moved_small, 1000);
  EXPECT_GT((dz.theta_hat.back() - rac.theta_hat.back()).norm(), 1e-3);
}

// Only the zero strategy sets theta_hat to 0 at an onset: rac keeps it.
TEST(ScratchParts, TheZeroStrategyResetsThetaHatAtEachOnset) {
  const SimResult zero = run("pa_zero", true);
  int onsets = 0;
  for (const Event& ev : zero.events) {
    if (ev.type != Event::Type::kOnset) continue;
    ++onsets;
    EXPECT_TRUE(ev.reset);
    EXPECT_EQ(ev.theta_hat_after.norm(), 0.0) << "t = " << ev.t;
    EXPECT_GT(ev.theta_hat_before.norm(), 0.0) << "t = " << ev.t;
  }
  EXPECT_GE(onsets, 3);
  for (const Event& ev : run("rac", true).events) {
    if (ev.type == Event::Type::kOnset) {
      EXPECT_EQ(ev.theta_hat_after, ev.theta_hat_before);
    }
  }
}

void expectRefused(const std::function<bool()>& registration, const std::string& name) {
  try {
    registration();
    ADD_FAILURE() << "registered: " << name;
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("'" + name + "'"), std::string::npos) << e.what();
  }
}

TEST(ScratchParts, ADuplicateOrAModeOfUnregisteredPartsIsRefusedByName) {
  const std::size_t laws = lawRegistry().size(), modes = modeRegistry().size();
  expectRefused([] { return registerLaw("deadzone", makeDeadzoneLaw); }, "deadzone");
  expectRefused([] { return registerLaw("mrac", makeDeadzoneLaw); }, "mrac");  // built in
  expectRefused([] { return registerStrategy("zero", makeZeroPreadaptation); }, "zero");
  expectRefused([] { return registerStrategy("paper_rac", makeZeroPreadaptation); }, "paper_rac");
  expectRefused([] { return registerMode("pa_zero", "", "mrac", "zero", false); }, "pa_zero");
  expectRefused([] { return registerMode("rac", "", "mrac", "zero", false); }, "rac");  // table
  expectRefused([] { return registerMode("x", "", "nolaw", "zero", false); }, "nolaw");
  expectRefused([] { return registerMode("x", "", "mrac", "nostrategy", false); }, "nostrategy");
  EXPECT_EQ(lawRegistry().size(), laws);
  EXPECT_EQ(modeRegistry().size(), modes);
  EXPECT_EQ(findMode("x"), nullptr);
}

}  // namespace
}  // namespace preadaptive_mrac
