// Controller::setTunables: tunables queued between samples take effect at the next step, an
// invalid set is refused naming its key, and a set equal to the current one changes nothing.

#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <vector>

#include "preadaptive_mrac/core/closed_loop.hpp"
#include "preadaptive_mrac/core/controller/controller.hpp"
#include "preadaptive_mrac/core/controller/tunables.hpp"
#include "test_helpers.hpp"

namespace preadaptive_mrac {
namespace {

struct Trace {
  std::vector<double> u, e, th0;
  std::vector<int> event_type;  // -1: none
  std::vector<bool> applied;
};

// Scenario 1 in lockstep with a hook called before each step k (it may queue tunables).
Trace run(const RunConfig& rc, const std::string& mode, std::int64_t steps,
          const std::function<void(std::int64_t, Controller*)>& hook) {
  ControllerConfig cc = rc.controller;
  cc.mode = mode;
  Controller ctl(designModelOf(rc.plant, cc), cc);
  ScenarioPlant plant(rc.plant, rc.scenario, cc.sample_time);
  Trace tr;
  for (std::int64_t k = 0; k < steps && !plant.done(); ++k) {
    if (hook) hook(k, &ctl);
    const double applied = plant.lastApplied();
    const StepOutput out = ctl.step(test::lockstepInput(plant, &applied));
    tr.u.push_back(out.u);
    tr.e.push_back(out.e);
    tr.th0.push_back(out.theta_hat[0]);
    tr.event_type.push_back(out.event ? static_cast<int>(out.event->type) : -1);
    tr.applied.push_back(out.tunables_applied);
    plant.advance(out.u);
  }
  return tr;
}

bool bitEqual(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(Tunables, SameValuesChangeNothingBitForBit) {
  const RunConfig rc = test::packageConfig("1");
  for (const char* mode : {"rac", "pa", "pa_learn", "pa_learn_exact", "pa_robust"}) {
    const std::int64_t steps = 30000;  // past the switches at 5 s and 20 s
    const Trace ref = run(rc, mode, steps, nullptr);
    // The same values queued at several steps (inside and outside phases).
    const Trace same = run(rc, mode, steps, [](std::int64_t k, Controller* c) {
      if (k % 2500 == 7) c->setTunables(c->tunables());
    });
    EXPECT_TRUE(bitEqual(ref.u, same.u)) << mode;
    EXPECT_TRUE(bitEqual(ref.th0, same.th0)) << mode;
    EXPECT_EQ(ref.event_type, same.event_type) << mode;
    EXPECT_TRUE(same.applied[7]);
    EXPECT_FALSE(same.applied[8]);
    EXPECT_FALSE(ref.applied[7]);
  }
}

TEST(Tunables, ChangeTakesEffectAtTheNextStep) {
  const RunConfig rc = test::packageConfig("1");
  const std::int64_t k_change = 10000, steps = 30000;  // between the switches at 5 s and 20 s
  const Trace ref = run(rc, "pa_learn", steps, nullptr);
  ControllerTunables seen;
  const Trace chg = run(rc, "pa_learn", steps, [&](std::int64_t k, Controller* c) {
    if (k == k_change) {
      ControllerTunables t = c->tunables();
      t.c_ed = 0.015;  // the paper's 0.02 misses the switch at 20 s, 0.015 sees it
      c->setTunables(t);
      EXPECT_TRUE(c->tunablesPending());
      EXPECT_EQ(c->tunables().c_ed, rc.controller.c_ed);  // not yet in effect
    }
    if (k == k_change + 1) seen = c->tunables();
  });
  EXPECT_EQ(seen.c_ed, 0.015);
  for (std::int64_t k = 0; k < steps; ++k)
    EXPECT_EQ(chg.applied[static_cast<size_t>(k)], k == k_change) << k;
  // Before the change: the same run bit for bit.
  const auto n = static_cast<std::ptrdiff_t>(k_change);
  EXPECT_TRUE(bitEqual(std::vector<double>(ref.u.begin(), ref.u.begin() + n),
                       std::vector<double>(chg.u.begin(), chg.u.begin() + n)));
  // After it: an onset at the switch at 20 s in the changed run, none in the reference.
  auto onsets = [&](const Trace& t) {
    int c = 0;
    for (std::int64_t k = k_change; k < steps; ++k)
      c += t.event_type[static_cast<size_t>(k)] == static_cast<int>(Event::Type::kOnset);
    return c;
  };
  EXPECT_EQ(onsets(ref), 0);
  EXPECT_GT(onsets(chg), 0);
}

TEST(Tunables, InvalidValuesAreRefusedNamingTheKey) {
  const RunConfig rc = test::packageConfig("1");
  Controller ctl(designModelOf(rc.plant, rc.controller), rc.controller);
  const ControllerTunables before = ctl.tunables();
  auto refused = [&](const ControllerTunables& t, const std::string& key) {
    try {
      ctl.setTunables(t);
      ADD_FAILURE() << "accepted, expected a problem with " << key;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
    EXPECT_FALSE(ctl.tunablesPending());
    EXPECT_TRUE(diffTunables(before, ctl.tunables()).empty());
  };
  ControllerTunables t = before;
  t.c_ed = 0.0;
  refused(t, "controller.attention.c_ed: must be in [1e-06, 10], got 0");
  t = before;
  t.hysteresis = before.c_e;  // must stay below c_e
  refused(t, "controller.attention.hysteresis");
  t = before;
  t.gamma = std::numeric_limits<double>::infinity();
  refused(t, "controller.adaptation.gamma: must be finite");
  t = before;
  t.robust.margin = 1.5;
  refused(t, "controller.robust.margin");
  t = before;
  t.projection = true;
  t.theta_max = 1e-3;  // theta_hat0 = 0 lies inside; fine
  t.projection_epsilon = 0.0;
  refused(t, "controller.projection.epsilon");
  // ROS key style.
  KeyStyle ros;
  ros.root = "/mrac_controller/";
  ros.separator = '/';
  t = before;
  t.c_e = -1.0;
  const auto p = validateTunables(ctl.config(), t, ros);
  ASSERT_FALSE(p.empty());
  EXPECT_NE(p[0].find("/mrac_controller/controller/attention/c_e"), std::string::npos) << p[0];
}

TEST(Tunables, DiffNamesTheChangedKeys) {
  const RunConfig rc = test::packageConfig("1");
  ControllerTunables a = ControllerTunables::of(rc.controller), b = a;
  b.c_ed = 0.05;
  b.robust.use_network = !a.robust.use_network;
  const auto d = diffTunables(a, b);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d[0].key, "attention.c_ed");
  EXPECT_EQ(d[0].old_value, a.c_ed);
  EXPECT_EQ(d[0].new_value, 0.05);
  EXPECT_EQ(d[1].key, "robust.use_network");
  EXPECT_EQ(tunableEntries(a).size(), 32u);
}

TEST(Tunables, ThresholdChangeIsNoCrossing) {
  // |e| = 4 mrad sits below c_e = 5 mrad; lowering c_e to 3 mrad between samples must not be
  // seen as |e| crossing the threshold (the last sample is re-evaluated).
  Attention a(0.005, 0.02);
  EXPECT_EQ(a.update(0.004, 1.0), Attention::Result::kNone);
  a.setThresholds(0.003, 0.02, 0, 0.0);
  EXPECT_EQ(a.update(0.004, 1.0), Attention::Result::kNone);
  EXPECT_EQ(a.update(0.002, 0.0), Attention::Result::kIgnoredRecovery);  // it is above now
  EXPECT_EQ(a.update(0.004, 1.0), Attention::Result::kOnset);
}

TEST(Tunables, RobustWindowChangeRestartsDetectionAndRuns) {
  const RunConfig rc = test::packageConfig("1");
  const Trace tr = run(rc, "pa_robust", 30000, [](std::int64_t k, Controller* c) {
    if (k == 10000) {
      ControllerTunables t = c->tunables();
      t.robust.detect_window *= 2.0;
      t.robust.verify_time = std::max(t.robust.verify_time, t.robust.detect_window);
      t.robust.memory_size = 1;
      c->setTunables(t);
    }
  });
  ASSERT_EQ(tr.u.size(), 30000u);
  for (double u : tr.u) ASSERT_TRUE(std::isfinite(u));
  EXPECT_TRUE(tr.applied[10000]);
}

}  // namespace
}  // namespace preadaptive_mrac
