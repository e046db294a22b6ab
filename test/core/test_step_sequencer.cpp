// The controller node's step without ROS: StepSequencer on numbers (the order of the plant's
// states, rejection, staleness, the controller step).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "preadaptive_mrac/core/step_sequencer.hpp"
#include "test_helpers.hpp"

using namespace preadaptive_mrac;

namespace {

constexpr double kDt = 0.001, kTimeout = 0.05;

struct Fixture {
  RunConfig cfg = test::packageConfig("1");
  Controller ctl{designModelOf(cfg.plant, cfg.controller), cfg.controller};
  StepSequencer seq{&ctl, cfg.plant.n(), kDt, kTimeout, StalePolicy::kBaselineHold};
  Vec x = Vec::Zero(3);

  // State `step` at t = step dt, x = (0, 0.01 step, 0); refreshed and judged at its own time.
  SampleOutcome send(std::uint64_t step, std::uint64_t total = 0, double dt = kDt) {
    PlantSample s;
    s.step = step;
    s.t = static_cast<double>(step) * kDt;
    s.dt = dt;
    x << 0.0, 0.01 * static_cast<double>(step % 7), 0.0;
    s.x = x.data();
    s.size = 3;
    s.r = 0.1;
    s.total_steps = total;
    return seq.onSample(s, nullptr, s.t, s.t);
  }
};

StepOutput stepDirect(Controller* c, std::uint64_t step) {
  Vec x(3);
  x << 0.0, 0.01 * static_cast<double>(step % 7), 0.0;
  StepInput in;
  in.t = static_cast<double>(step) * kDt;
  in.x = &x;
  in.r = 0.1;
  return c->step(in);
}

}  // namespace

TEST(StepSequencer, InOrderStatesStepTheControllerAsADirectCallWould) {
  Fixture f;
  Controller ref(designModelOf(f.cfg.plant, f.cfg.controller), f.cfg.controller);
  for (std::uint64_t k = 0; k < 50; ++k) {
    const SampleOutcome o = f.send(k);
    ASSERT_EQ(o.kind, SampleOutcome::Kind::kStepped) << k;
    EXPECT_EQ(o.out.u, stepDirect(&ref, k).u) << k;
    EXPECT_FALSE(o.restarted_after || o.missing || o.finished || o.stale_for);
  }
  EXPECT_EQ(f.seq.steps(), 50);
  EXPECT_EQ(f.seq.gaps(), 0);
}

TEST(StepSequencer, ARepeatIsNotSteppedAGapIsCountedARestartResets) {
  Fixture f;
  Controller ref(designModelOf(f.cfg.plant, f.cfg.controller), f.cfg.controller);
  for (std::uint64_t k = 0; k < 5; ++k) f.send(k), stepDirect(&ref, k);
  EXPECT_EQ(f.send(4).kind, SampleOutcome::Kind::kRepeated);
  EXPECT_EQ(f.seq.steps(), 5);
  const SampleOutcome gap = f.send(9);
  ASSERT_EQ(gap.kind, SampleOutcome::Kind::kStepped);
  ASSERT_TRUE(gap.missing);
  EXPECT_EQ(gap.missing->first, 5u);
  EXPECT_EQ(gap.missing->second, 8u);
  EXPECT_EQ(gap.out.u, stepDirect(&ref, 9).u);
  EXPECT_EQ(f.seq.gaps(), 1);
  // Step 0 again: a new plant run, the controller reset (the same answer as a fresh one's).
  const SampleOutcome restart = f.send(0);
  ASSERT_EQ(restart.kind, SampleOutcome::Kind::kStepped);
  ASSERT_TRUE(restart.restarted_after);
  EXPECT_EQ(*restart.restarted_after, 9u);
  Controller fresh(designModelOf(f.cfg.plant, f.cfg.controller), f.cfg.controller);
  EXPECT_EQ(restart.out.u, stepDirect(&fresh, 0).u);
  EXPECT_EQ(f.seq.restarts(), 1);
}

TEST(StepSequencer, AMalformedStateIsRejectedAndAWrongSampleTimeRefused) {
  Fixture f;
  EXPECT_EQ(f.send(0, 0, 2 * kDt).kind, SampleOutcome::Kind::kBadSampleTime);
  EXPECT_EQ(f.seq.steps(), 0);
  ASSERT_EQ(f.send(0).kind, SampleOutcome::Kind::kStepped);
  PlantSample s;
  s.step = 1;
  s.t = kDt;
  s.dt = kDt;
  const double bad[3] = {0.0, std::numeric_limits<double>::quiet_NaN(), 0.0};
  s.x = bad;
  s.size = 3;
  const SampleOutcome o = f.seq.onSample(s, nullptr, s.t, s.t);
  EXPECT_EQ(o.kind, SampleOutcome::Kind::kRejected);
  EXPECT_NE(o.why.find("x[1]"), std::string::npos) << o.why;
  EXPECT_EQ(f.seq.steps(), 1);
  EXPECT_EQ(f.seq.guard().rejected(), 1u);
  // The safe command holds the baseline on the last valid state (x = 0 at step 0).
  EXPECT_EQ(f.seq.safeCommand(), 0.0);
}

TEST(StepSequencer, StaleInputGivesSafeCommandsForTheNextStepsUntilAValidState) {
  Fixture f;
  EXPECT_FALSE(f.seq.onTimer(1.0)) << "nothing to hold before the first valid state";
  for (std::uint64_t k = 0; k <= 10; ++k) f.send(k);
  const double t10 = 10 * kDt;
  EXPECT_FALSE(f.seq.onTimer(t10 + kTimeout)) << "not stale at the timeout itself";
  const auto first = f.seq.onTimer(t10 + kTimeout + 0.001);
  ASSERT_TRUE(first);
  EXPECT_TRUE(first->began);
  EXPECT_EQ(first->step, 11u);
  EXPECT_DOUBLE_EQ(first->t, 11 * kDt);
  const auto second = f.seq.onTimer(t10 + kTimeout + 0.002);
  ASSERT_TRUE(second);
  EXPECT_FALSE(second->began);
  EXPECT_EQ(second->step, 12u);
  EXPECT_TRUE(f.seq.stale());
  EXPECT_EQ(f.seq.staleEpisodes(), 1);
  // Step 11 arrives late: valid again, after the time it was stale.
  PlantSample s;
  s.step = 11;
  s.t = 11 * kDt;
  s.dt = kDt;
  f.x << 0.0, 0.0, 0.0;
  s.x = f.x.data();
  s.size = 3;
  const double now = t10 + kTimeout + 0.0035;
  const SampleOutcome o = f.seq.onSample(s, nullptr, now, now);
  ASSERT_EQ(o.kind, SampleOutcome::Kind::kStepped);
  ASSERT_TRUE(o.stale_for);
  EXPECT_NEAR(*o.stale_for, 0.0025, 1e-12);
  EXPECT_FALSE(f.seq.stale());
}

TEST(StepSequencer, NoStaleCommandsAfterThePlantsLastStep) {
  Fixture f;
  for (std::uint64_t k = 0; k < 19; ++k) EXPECT_FALSE(f.send(k, 20).finished);
  EXPECT_TRUE(f.send(19, 20).finished);
  EXPECT_FALSE(f.seq.onTimer(1.0));
  // A restarted plant's state clears it: stale again after its silence.
  f.send(0, 20);
  EXPECT_TRUE(f.seq.onTimer(1.0));
}

// The plant-lost clock: 2 s of silence at 1 ms ticks is 2 s; a 7 s pause of the asking process
// (its timer does not run) counts 0.5 s, so a plant paused with it is not gone when both resume,
// and a plant that is gone for good is still found.
TEST(SilenceClock, CountsTheAskersOwnPausesAtMostMaxGap) {
  SilenceClock c(0.5);
  EXPECT_EQ(c.silentFor(10.0), 0.0);  // before the first state
  c.heard(10.0);
  double s = 0.0;
  for (int k = 1; k <= 2000; ++k) s = c.silentFor(10.0 + 0.001 * k);
  EXPECT_NEAR(s, 2.0, 1e-9);
  c.heard(12.0);
  EXPECT_NEAR(c.silentFor(19.0), 0.5, 1e-12);  // paused 7 s
  c.heard(19.001);                             // the plant resumed with it
  EXPECT_EQ(c.silentFor(19.002) < 0.002, true);
  // Gone for good while the asker runs: the silence grows with its ticks again.
  s = c.silentFor(19.501);
  for (int k = 1; k <= 1500; ++k) s = c.silentFor(19.501 + 0.001 * k);
  EXPECT_NEAR(s, 2.0, 1e-9);
  EXPECT_EQ(c.silentFor(18.0), s);  // a clock that steps back adds nothing
}
