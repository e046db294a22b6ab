// Margins by simulation: the early stop, the bisection's bracket, and the statuses
// at the ends of the search intervals.

#include <gtest/gtest.h>

#include "preadaptive_mrac/core/margins.hpp"
#include "test_helpers.hpp"

using namespace preadaptive_mrac;

namespace {
struct Fixture {
  RunConfig cfg;
  ControllerFactory make;
  explicit Fixture(double gamma) : cfg(test::packageConfig("1")) {
    cfg.controller.gamma = gamma;
    make = [this]() {
      return std::make_unique<Controller>(designModelOf(cfg.plant, cfg.controller), cfg.controller);
    };
  }
  double dt() const { return cfg.controller.sample_time; }
};
}  // namespace

TEST(Margins, UnstableRunStopsAtTheBound) {
  Fixture f(1000.0);
  f.cfg.plant.dynamics.delay = 0.2;
  auto ctl = f.make();
  ClosedLoop loop(f.cfg.plant, f.cfg.scenario, ctl.get());
  SimOptions opt;
  opt.stop_above = 0.2;
  const SimResult res = loop.run(opt);
  EXPECT_TRUE(res.stopped);
  EXPECT_LT(res.steps, 60000);
  EXPECT_GT(res.metrics.peak_abs_e, 0.2);
  EXPECT_FALSE(runWithinBound(f.cfg.plant, f.cfg.scenario, f.dt(), f.make, 0.2));
  f.cfg.plant.dynamics.delay = 0.0;
  EXPECT_TRUE(runWithinBound(f.cfg.plant, f.cfg.scenario, f.dt(), f.make, 0.2));
}

// The bracket holds what it says: stable at its lower end, unstable at its upper end, whole
// samples, at most the resolution apart.
TEST(Margins, DelayBracketIsStableBelowAndUnstableAbove) {
  Fixture f(1000.0);
  MarginOptions opt;
  opt.max_delay = 0.5;
  const MarginsResult m = findMargins(f.cfg.plant, f.cfg.scenario, f.dt(), f.make, opt);
  ASSERT_TRUE(m.nominal_stable);
  ASSERT_EQ(m.delay.status, "bracketed");
  EXPECT_LE(m.delay.unstable - m.delay.stable, 0.004 + 1e-12);
  EXPECT_GT(m.delay.unstable, m.delay.stable);
  const double steps = m.delay.stable / f.dt();
  EXPECT_NEAR(steps, std::round(steps), 1e-9);
  PlantConfig p = f.cfg.plant;
  p.dynamics.delay = m.delay.stable;
  EXPECT_TRUE(runWithinBound(p, f.cfg.scenario, f.dt(), f.make, opt.bound));
  p.dynamics.delay = m.delay.unstable;
  EXPECT_FALSE(runWithinBound(p, f.cfg.scenario, f.dt(), f.make, opt.bound));
  // A faster adaptation leaves less delay margin (the paper's trade-off): gamma 100 > 1000's.
  Fixture slow(100.0);
  const MarginsResult ms =
      findMargins(slow.cfg.plant, slow.cfg.scenario, slow.dt(), slow.make, opt);
  EXPECT_GT(ms.delay.stable, m.delay.unstable);
}

TEST(Margins, StatusesAtTheEndsOfTheIntervals) {
  Fixture f(1000.0);
  MarginOptions opt;
  opt.max_delay = 0.03;  // below gamma 1000's margin: still stable at the top
  MarginsResult m = findMargins(f.cfg.plant, f.cfg.scenario, f.dt(), f.make, opt);
  EXPECT_EQ(m.delay.status, "stable_at_limit");
  EXPECT_DOUBLE_EQ(m.delay.stable, 0.03);
  EXPECT_EQ(m.delay.runs, 1);
  opt.bound = 1e-4;  // even the nominal run breaks it
  m = findMargins(f.cfg.plant, f.cfg.scenario, f.dt(), f.make, opt);
  EXPECT_FALSE(m.nominal_stable);
  EXPECT_EQ(m.delay.status, "unstable_at_nominal");
  EXPECT_EQ(m.effectiveness_low.status, "unstable_at_nominal");
  EXPECT_EQ(m.runs, 1);
}

// With a delay in the plant the gain search keeps it; with gamma 1000 and 80 ms, a stronger
// elevator (Lambda about 1.38) breaks the bound: the upper gain margin is bracketed within 0.01.
TEST(Margins, GainMarginsBracketWithTheConfiguredDelay) {
  Fixture f(1000.0);
  f.cfg.plant.dynamics.delay = 0.08;
  const MarginsResult m = findMargins(f.cfg.plant, f.cfg.scenario, f.dt(), f.make);
  ASSERT_EQ(m.effectiveness_high.status, "bracketed");
  EXPECT_LE(m.effectiveness_high.unstable - m.effectiveness_high.stable, 0.01 + 1e-12);
  Scenario s = f.cfg.scenario;
  s.effectiveness = {{s.endTime(), m.effectiveness_high.stable}};
  EXPECT_TRUE(runWithinBound(f.cfg.plant, s, f.dt(), f.make, 0.2));
  s.effectiveness = {{s.endTime(), m.effectiveness_high.unstable}};
  EXPECT_FALSE(runWithinBound(f.cfg.plant, s, f.dt(), f.make, 0.2));
}
