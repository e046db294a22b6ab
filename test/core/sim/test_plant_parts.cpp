// The plant simulator's parts, each alone and in the ScenarioPlant: transport delay,
// servo lag, the chain with the limits and its saturation count, elevator effectiveness, Dryden
// turbulence, and the validation of their keys.

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "preadaptive_mrac/core/schema/param_table.hpp"
#include "preadaptive_mrac/core/sim/actuator.hpp"
#include "preadaptive_mrac/core/sim/scenario_plant.hpp"
#include "preadaptive_mrac/core/sim/turbulence.hpp"
#include "test_helpers.hpp"

using namespace preadaptive_mrac;

namespace {
ParamValue num(double v) { return ParamValue::makeDouble(v); }

ParamValue segment(double until, const char* key, double value) {
  ParamValue s = ParamValue::makeMap();
  s.setPath("until", num(until));
  s.setPath(key, num(value));
  return s;
}

// Every problem readRunConfig reports for `t`, joined ("" when valid).
std::string problems(const ParamValue& t) {
  try {
    readRunConfig(t);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

// A slowly varying command that is not constant, to drive the plant.
double command(std::int64_t k) { return 0.05 * std::sin(0.003 * static_cast<double>(k)); }
}  // namespace

TEST(TransportDelay, CommandOfStepKActsFromStepKPlusD) {
  TransportDelay d(3);
  EXPECT_EQ(TransportDelay::stepsFor(0.0034, 0.001), 3);
  EXPECT_EQ(TransportDelay::stepsFor(0.0036, 0.001), 4);
  std::vector<double> out;
  for (int k = 0; k < 8; ++k) out.push_back(d.push(k + 1.0));
  // Nothing has arrived for the first three steps: the actuator's initial state, 0.
  EXPECT_EQ(out, (std::vector<double>{0, 0, 0, 1, 2, 3, 4, 5}));
  d.reset();
  EXPECT_EQ(d.push(9.0), 0.0);
  TransportDelay none(0);
  EXPECT_EQ(none.push(2.5), 2.5);
  EXPECT_THROW(TransportDelay(-1), std::invalid_argument);
}

TEST(ServoLag, ExactStepResponseAndPassThrough) {
  const double T = 0.05, dt = 0.001;
  ServoLag lag(T, dt);
  for (int k = 1; k <= 200; ++k) {
    const double y = lag.step(1.0);
    // The exact discretisation of 1/(T s + 1) for a held input: y_k = 1 - exp(-k dt / T).
    EXPECT_NEAR(y, 1.0 - std::exp(-k * dt / T), 1e-14) << k;
  }
  ServoLag none(0.0, dt);
  EXPECT_FALSE(none.active());
  EXPECT_EQ(none.step(0.3), 0.3);
  EXPECT_THROW(ServoLag(-0.1, dt), std::invalid_argument);
}

TEST(ActuatorChain, DelayThenLagThenLimits) {
  const double dt = 0.001;
  ActuatorDynamics dyn;
  dyn.delay = 0.002;
  dyn.time_constant = 0.01;
  ActuatorLimits lim;
  lim.enabled = true;
  lim.max_deflection = 0.3;
  lim.max_rate = 5.0;
  ActuatorChain chain(dyn, lim, dt);
  TransportDelay d(2);
  ServoLag lag(0.01, dt);
  double prev = 0.0;
  int limited = 0;
  for (int k = 0; k < 400; ++k) {
    const double u = k < 200 ? 1.0 : -1.0;  // steps far beyond both limits
    const double v = lag.step(d.push(u));
    const double want = lim.apply(v, prev, dt);
    prev = want;
    EXPECT_EQ(chain.apply(u), want) << k;
    EXPECT_EQ(chain.limited(), want != v) << k;
    limited += chain.limited() ? 1 : 0;
  }
  EXPECT_GT(limited, 100);
  ActuatorChain ideal(ActuatorDynamics{}, ActuatorLimits{}, dt);
  EXPECT_TRUE(ideal.identity());
  EXPECT_EQ(ideal.apply(0.7), 0.7);
}

// The saturation count is the steps in which the limits changed the signal: with lag and
// delay on and limits no command reaches, it stays 0, although the deflection differs from the
// command at every step (the count "applied != command" would report every step).
TEST(ScenarioPlant, SaturationCountWithLagAndDelay) {
  RunConfig cfg = test::packageConfig("1");
  cfg.plant.dynamics.delay = 0.02;
  cfg.plant.dynamics.time_constant = 0.05;
  cfg.plant.actuator.enabled = true;
  cfg.plant.actuator.max_deflection = 10.0;
  cfg.plant.actuator.max_rate = 100.0;
  ScenarioPlant sim(cfg.plant, cfg.scenario, 0.001);
  int differs = 0;
  for (int k = 0; k < 3000; ++k) {
    sim.advance(command(k) + 0.01);
    differs += sim.lastApplied() != sim.lastCommand() ? 1 : 0;
  }
  EXPECT_EQ(sim.limitedSteps(), 0);
  EXPECT_EQ(differs, 3000);
  // Tight limits: the count is what the limits did.
  cfg.plant.actuator.max_deflection = 0.02;
  ScenarioPlant tight(cfg.plant, cfg.scenario, 0.001);
  std::int64_t by_hand = 0;
  for (int k = 0; k < 3000; ++k) {
    tight.advance(command(k) + 0.01);
    by_hand += tight.lastLimited() ? 1 : 0;
    EXPECT_LE(std::abs(tight.lastApplied()), 0.02);
  }
  EXPECT_EQ(tight.limitedSteps(), by_hand);
  EXPECT_GT(by_hand, 500);
}

// A delay of d steps is the undelayed plant fed the command of d steps earlier (0 before).
TEST(ScenarioPlant, DelayIsTheShiftedCommand) {
  RunConfig cfg = test::packageConfig("1");
  PlantConfig delayed = cfg.plant;
  delayed.dynamics.delay = 0.0254;  // rounds to 25 steps
  ScenarioPlant a(delayed, cfg.scenario, 0.001), b(cfg.plant, cfg.scenario, 0.001);
  for (int k = 0; k < 2000; ++k) {
    a.advance(command(k));
    b.advance(k >= 25 ? command(k - 25) : 0.0);
    ASSERT_EQ(a.state(), b.state()) << k;
    EXPECT_EQ(a.lastApplied(), b.lastApplied());
  }
}

// Lambda scales the applied deflection, at the value of the step's midpoint (as theta).
TEST(ScenarioPlant, EffectivenessScalesTheAppliedElevator) {
  RunConfig cfg = test::packageConfig("1");
  Scenario lossy = cfg.scenario;
  lossy.effectiveness = {{1.0, 1.0}, {60.0, 0.5}};
  ScenarioPlant a(cfg.plant, lossy, 0.001), b(cfg.plant, cfg.scenario, 0.001);
  for (int k = 0; k < 2000; ++k) {
    const double lambda = k < 1000 ? 1.0 : 0.5;  // step [0.999, 1.000] still has Lambda 1
    EXPECT_EQ(a.effectiveness(), lambda) << k;
    a.advance(command(k));
    b.advance(lambda * command(k));
    ASSERT_EQ(a.state(), b.state()) << k;
    EXPECT_EQ(a.lastApplied(), command(k));  // the surface angle, before Lambda
  }
  EXPECT_TRUE(a.hasConditions());
  EXPECT_FALSE(b.hasConditions());
}

// The conditions record: every field has exactly one row of the table, the names
// are distinct, and the record the closed loop keeps for step k is the plant's: the values
// held over the step (read before it) with what the step did (read after it).
TEST(PlantConditions, OneRowPerFieldAndTheLoopKeepsThePlantsRecord) {
  EXPECT_EQ(sizeof(PlantConditions), kPlantConditionTable.size() * sizeof(double))
      << "a field of PlantConditions without its row in kPlantConditionTable (or the reverse)";
  for (size_t i = 0; i < kPlantConditionTable.size(); ++i)
    for (size_t j = 0; j < i; ++j) {
      EXPECT_STRNE(kPlantConditionTable[i].name, kPlantConditionTable[j].name);
      EXPECT_NE(kPlantConditionTable[i].field, kPlantConditionTable[j].field);
    }
  RunConfig cfg = test::packageConfig("1");
  cfg.plant.actuator.enabled = true;
  cfg.plant.actuator.max_rate = 0.5;
  cfg.plant.dynamics.time_constant = 0.05;
  cfg.plant.turbulence.enabled = true;
  cfg.plant.turbulence.sigma_w = 1.5;
  cfg.plant.turbulence.length_scale = 533.4;
  cfg.scenario.effectiveness = {{0.5, 1.0}, {60.0, 0.7}};
  cfg.scenario.theta.resize(1);
  cfg.scenario.theta[0].until = 1.0;
  cfg.scenario.reference.resize(1);
  cfg.scenario.reference[0].until = 1.0;
  const SimResult res = test::simulate(cfg);
  ScenarioPlant sim(cfg.plant, cfg.scenario, cfg.controller.sample_time);
  ASSERT_EQ(res.series.conditions.size(), static_cast<size_t>(sim.totalSteps()));
  int limited = 0;
  for (size_t k = 0; k < res.series.conditions.size(); ++k) {
    const PlantConditions& c = res.series.conditions[k];
    EXPECT_EQ(c.effectiveness, sim.effectiveness()) << k;
    EXPECT_EQ(c.w_gust, sim.gust()) << k;
    sim.advance(res.series.u[k]);
    EXPECT_EQ(c.u_applied, sim.lastApplied()) << k;
    EXPECT_EQ(c.plant_limited, sim.lastLimited() ? 1.0 : 0.0) << k;
    limited += sim.lastLimited() ? 1 : 0;
  }
  EXPECT_EQ(limited, res.plant_limited_steps);
  EXPECT_EQ(res.series.conditions[0].effectiveness, 1.0);
  EXPECT_EQ(res.series.conditions.back().effectiveness, 0.7);
}

// The gust enters as alpha_g = w_g / V through the alpha column of A in the alpha and q rows
// (not the integrator's).
TEST(ScenarioPlant, GustEntersThroughTheAlphaColumn) {
  RunConfig cfg = test::packageConfig("1");
  PlantConfig gusty = cfg.plant;
  gusty.turbulence.enabled = true;
  gusty.turbulence.sigma_w = 2.0;
  gusty.turbulence.length_scale = 533.0;
  gusty.turbulence.seed = 4;
  ScenarioPlant a(gusty, cfg.scenario, 0.001);
  Plant p(cfg.plant);
  Vec d = Vec::Zero(3);
  for (int k = 0; k < 500; ++k) {
    const double ag = a.gust() * (1.0 / gusty.airspeed);
    d << 0.0, cfg.plant.A(1, 1) * ag, cfg.plant.A(2, 1) * ag;
    p.stepDisturbed(0.001, a.theta(), command(k), a.reference(), d);
    a.advance(command(k));
    ASSERT_EQ(a.state(), p.state()) << k;
  }
  // Reproducible, and independent of the measurement noise stream.
  PlantConfig noisy = gusty;
  noisy.noise.std = Vec::Constant(3, 1e-3);
  noisy.noise.seed = 99;
  ScenarioPlant b(gusty, cfg.scenario, 0.001), c(noisy, cfg.scenario, 0.001);
  for (int k = 0; k < 100; ++k) {
    EXPECT_EQ(b.gust(), c.gust());
    b.advance(0.0);
    c.advance(0.0);
  }
}

// Dryden: the standard deviation of w_g over a long run is sigma_w, and its spectrum follows
// Phi_w (shape, level and half-power frequency 2.058 V / L_w). The discretisation is exact for
// any dt, so the test samples at 50 ms to cover many correlation times cheaply.
TEST(DrydenGust, StandardDeviationAndSpectrum) {
  TurbulenceConfig tc;
  tc.enabled = true;
  tc.sigma_w = 1.5;
  tc.length_scale = 533.0;
  tc.seed = 11;
  const double V = 274.0, h = 0.05;
  DrydenGust g(tc, V, h);
  const int seg = 1024, nseg = 600;
  std::vector<double> w(static_cast<size_t>(seg) * nseg);
  double sum2 = 0.0;
  for (double& v : w) {
    v = g.value();
    sum2 += v * v;
    g.advance();
  }
  const double std_w = std::sqrt(sum2 / static_cast<double>(w.size()));
  EXPECT_NEAR(std_w, tc.sigma_w, 0.03 * tc.sigma_w);
  // Welch-averaged periodogram with a Hann window, one-sided density in (m/s)^2/(rad/s).
  const double pi = 3.14159265358979323846;
  std::vector<double> win(seg);
  double wsum2 = 0.0;
  for (int n = 0; n < seg; ++n) {
    win[n] = 0.5 - 0.5 * std::cos(2.0 * pi * n / seg);
    wsum2 += win[n] * win[n];
  }
  const int bins = 60;
  std::vector<double> psd(bins + 1, 0.0);
  for (int s = 0; s < nseg; ++s)
    for (int j = 1; j <= bins; ++j) {
      std::complex<double> acc = 0.0;
      const std::complex<double> step = std::polar(1.0, -2.0 * pi * j / seg);
      std::complex<double> rot = 1.0;
      for (int n = 0; n < seg; ++n) {
        acc += win[n] * w[static_cast<size_t>(s) * seg + n] * rot;
        rot *= step;
      }
      psd[j] += 2.0 * h / (2.0 * pi * wsum2) * std::norm(acc) / nseg;
    }
  const double dw = 2.0 * pi / (seg * h);
  for (int j = 2; j <= bins; ++j)  // bin 1 carries the window's leakage from 0
    EXPECT_NEAR(psd[j] / g.psd(j * dw), 1.0, 0.15) << "omega " << j * dw;
  // Half-power frequency: where the measured PSD falls through Phi_w(0) / 2.
  const double half = 0.5 * g.psd(0.0);
  double w_half = 0.0;
  for (int j = 2; j < bins; ++j)
    if (psd[j] >= half && psd[j + 1] < half)
      w_half = dw * (j + (psd[j] - half) / (psd[j] - psd[j + 1]));
  const double expect = std::sqrt(2.0 + std::sqrt(5.0)) * V / tc.length_scale;
  EXPECT_NEAR(w_half, expect, 0.06 * expect);
  // Reproducible from the seed.
  g.reset();
  EXPECT_EQ(g.value(), w[0]);
}

TEST(Config, ConditionsAreValidatedNamingTheKey) {
  ParamValue t = test::packageTree("1");
  t.setPath("plant.actuator.delay", num(-0.01));
  t.setPath("plant.actuator.time_constant", num(-1.0));
  t.setPath("plant.turbulence.enabled", ParamValue::makeBool(true));
  t.setPath("plant.turbulence.sigma_w", num(-1.0));
  t.setPath("plant.turbulence.length_scale", num(0.0));
  t.setPath("plant.turbulence.seed", ParamValue::makeInt(1));
  t.setPath("plant.operating_point.U", num(-3.0));
  ParamValue eff = ParamValue::makeList(
      {segment(20.0, "value", 1.0), segment(10.0, "value", 2.5), segment(60.0, "value", 0.0)});
  t.setPath("scenario.effectiveness", eff);
  const std::string all = problems(t);
  for (const char* key :
       // (the generic range check of params/plant.yaml's rows; it once said "must be
       // a finite number >= 0 [s], got -0.01" before: NaN and inf, below, are still refused)
       {"plant.actuator.delay: must be in [0, 3600], got -0.01",
        "plant.actuator.time_constant: must be >= 0, got -1",
        "plant.turbulence.sigma_w: must be >= 0, got -1",
        "plant.turbulence.length_scale: must be > 0, got 0",
        "plant.operating_point.U: must be > 0, got -3",
        "scenario.effectiveness.1.until: segments must end at increasing times",
        "scenario.effectiveness.1.value: elevator effectiveness must be in (0, 2]",
        "scenario.effectiveness.2.value: elevator effectiveness must be in (0, 2]"})
    EXPECT_NE(all.find(key), std::string::npos) << key << "\n" << all;
  // Delay and lag alone, without the limit keys, are a valid actuator section.
  ParamValue only = test::packageTree("1");
  only.child("plant").map().erase("actuator");
  only.setPath("plant.actuator.delay", num(0.05));
  EXPECT_EQ(problems(only), "");
  // Turbulence needs the airspeed.
  ParamValue no_u = test::packageTree("1");
  no_u.child("plant").map().erase("operating_point");
  no_u.setPath("plant.turbulence.enabled", ParamValue::makeBool(true));
  no_u.setPath("plant.turbulence.sigma_w", num(1.0));
  no_u.setPath("plant.turbulence.length_scale", num(533.0));
  no_u.setPath("plant.turbulence.seed", ParamValue::makeInt(0));
  EXPECT_NE(problems(no_u).find("plant.operating_point.U: required"), std::string::npos)
      << problems(no_u);
  // A schedule that ends early.
  ParamValue early = test::packageTree("1");
  early.setPath("scenario.effectiveness", ParamValue::makeList({segment(30.0, "value", 0.5)}));
  EXPECT_NE(problems(early).find("scenario.effectiveness: the last effectiveness segment"),
            std::string::npos);
}

// the physical fault schedule's keys (Scenario::kFaultKeys) refused out of range
// naming the key, and on the linear plant naming the section.
TEST(Config, FaultsAreValidatedNamingTheKey) {
  ParamValue t = test::packageTree("1");
  t.setPath("plant.engine", ParamValue::makeString("jsbsim"));
  t.setPath(
      "scenario.faults",
      ParamValue::makeList({segment(20.0, "cg_shift", 0.5), segment(40.0, "pitch_damping", -1.0),
                            segment(60.0, "elevator_effectiveness", 2.5)}));
  const std::string all = problems(t);
  for (const char* key :
       {"scenario.faults.0.cg_shift: the CG shift [fraction of the chord, + aft] must be in "
        "[-0.3, 0.3], got 0.5",
        "scenario.faults.1.pitch_damping: the pitch damping multiplier must be in [0, 2], got -1",
        "scenario.faults.2.elevator_effectiveness: the elevator effectiveness multiplier must be "
        "in [0, 2], got 2.5"})
    EXPECT_NE(all.find(key), std::string::npos) << key << "\n" << all;
  t.setPath("scenario.faults", ParamValue::makeList({segment(60.0, "cg_shift", 0.05)}));
  EXPECT_EQ(problems(t), "");
  t.setPath("plant.engine", ParamValue::makeString("linear"));
  EXPECT_NE(problems(t).find("scenario.faults: physical faults (CG shift, elevator effectiveness, "
                             "pitch damping) need plant.engine jsbsim"),
            std::string::npos)
      << problems(t);
}

// The plant's scalars read from params/plant.yaml's generated structs: NaN and inf
// are refused naming the key wherever the hand-written reader refused them (it said "finite").
TEST(Config, PlantScalarsRefuseNanAndInfNamingTheKey) {
  const char* keys[] = {"plant.actuator.delay",          "plant.actuator.time_constant",
                        "plant.actuator.max_deflection", "plant.actuator.max_rate",
                        "plant.turbulence.sigma_w",      "plant.turbulence.length_scale",
                        "plant.operating_point.U"};
  for (double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL}) {
    ParamValue t = test::packageTree("1");
    t.setPath("plant.turbulence.enabled", ParamValue::makeBool(true));
    t.setPath("plant.turbulence.seed", ParamValue::makeInt(1));
    for (const char* key : keys) t.setPath(key, num(bad));
    const std::string all = problems(t);
    for (const char* key : keys)
      EXPECT_NE(all.find(std::string(key) + ": expected a finite number"), std::string::npos)
          << key << " = " << bad << "\n"
          << all;
  }
}

// Seeds stay 64-bit: one above 2^32 is taken whole (not cut to an int), a negative one refused.
TEST(Config, PlantSeedsAreSixtyFourBit) {
  ParamValue t = test::packageTree("1");
  const std::int64_t big = (std::int64_t{1} << 40) + 7;
  t.setPath("plant.turbulence.enabled", ParamValue::makeBool(false));
  t.setPath("plant.turbulence.sigma_w", num(1.0));
  t.setPath("plant.turbulence.length_scale", num(533.4));
  t.setPath("plant.turbulence.seed", ParamValue::makeInt(big));
  t.setPath("plant.noise.std", ParamValue::makeList({num(0.0), num(0.0), num(0.0)}));
  t.setPath("plant.noise.seed", ParamValue::makeInt(big + 1));
  const RunConfig cfg = readRunConfig(t);
  EXPECT_EQ(cfg.plant.turbulence.seed, static_cast<std::uint64_t>(big));
  EXPECT_EQ(cfg.plant.noise.seed, static_cast<std::uint64_t>(big + 1));
  t.setPath("plant.turbulence.seed", ParamValue::makeInt(-1));
  t.setPath("plant.noise.seed", ParamValue::makeInt(-2));
  const std::string all = problems(t);
  EXPECT_NE(all.find("plant.turbulence.seed: must be >= 0, got -1"), std::string::npos) << all;
  EXPECT_NE(all.find("plant.noise.seed: must be >= 0, got -2"), std::string::npos) << all;
}

// The delay line is sized by kMaxDelay; the table's range of plant.actuator.delay (what the
// reader checks and the docs show) ends there.
TEST(Config, DelayRangeOfTheTableIsMaxDelay) {
  double hi = 0.0;
  ActuatorDynamicsParams p;
  ActuatorDynamicsParams::forEachScalar(p, [&](const ParamSpec& s, const double&) {
    if (std::string(s.key) == "actuator.delay") hi = s.check.hi;
  });
  EXPECT_EQ(hi, kMaxDelay);
  ParamValue t = test::packageTree("1");
  t.setPath("plant.actuator.delay", num(kMaxDelay + 1.0));
  EXPECT_NE(problems(t).find("plant.actuator.delay: must be in [0, 3600], got 3601"),
            std::string::npos)
      << problems(t);
}

// the flight envelope. The monitor keeps the first exit, names its bound and key,
// and a state or command that is not finite is flagged whatever came first.
TEST(Envelope, FirstExitKeptWithItsBoundAndNonFiniteFlagged) {
  FlightEnvelope env;  // the table's B-747 defaults
  EXPECT_TRUE(env.enabled);
  EXPECT_DOUBLE_EQ(env.max_alpha, 0.2618);
  EnvelopeMonitor m(env, 1);
  PlantConditions c;
  Vec x(3);
  x << 0.0, 0.1, 0.1;
  m.checkState(1, 0.001, x, 0.0, c);
  m.checkCommand(1, 0.001, 1.0, x, c);
  EXPECT_FALSE(m.exit().exited);
  x << 0.0, -0.3, 0.5;  // alpha and q both beyond: alpha is named
  m.checkState(7, 0.007, x, 0.2, c);
  ASSERT_TRUE(m.exit().exited);
  EXPECT_EQ(m.exit().bound, "alpha");
  EXPECT_EQ(m.exit().key, "max_alpha");
  EXPECT_EQ(m.exit().step, 7);
  EXPECT_DOUBLE_EQ(m.exit().value, 0.3);
  EXPECT_NE(m.exit().describe().find("plant.envelope.max_alpha"), std::string::npos);
  EXPECT_EQ(m.exit().describe().rfind("t = 0.007 s (step 7): |alpha| = 0.3 rad", 0), 0u)
      << m.exit().describe();
  m.checkCommand(8, 0.008, 2.0, x, c);  // a later exit does not replace the first
  EXPECT_EQ(m.exit().bound, "alpha");
  EXPECT_FALSE(m.nonFinite());
  x[2] = NAN;
  m.checkState(9, 0.009, x, 0.2, c);
  EXPECT_TRUE(m.nonFinite());
  EXPECT_EQ(m.exit().bound, "alpha");
  EXPECT_DOUBLE_EQ(m.exit().non_finite_t, 0.009);
  // Disabled: no bound, but a command that is not finite still ends the run.
  env.enabled = false;
  EnvelopeMonitor off(env, 1);
  x << 0.0, 5.0, 5.0;
  off.checkState(1, 0.001, x, 9.0, c);
  off.checkCommand(1, 0.001, 9.0, x, c);
  EXPECT_FALSE(off.exit().exited);
  off.checkCommand(2, 0.002, NAN, x, c);
  EXPECT_TRUE(off.nonFinite());
  EXPECT_EQ(off.exit().bound, "non_finite");
}

// The reproducer in the closed loop: theta turns destabilising at 5 s; the run leaves
// the envelope within a second of it, says when and where, and (finite) goes on to its end.
// A faster divergence reaches a state that is not finite and ends the run there.
TEST(Envelope, ClosedLoopRecordsTheExitAndEndsAtANonFiniteState) {
  RunConfig cfg = test::packageConfig("1");
  EXPECT_FALSE(test::simulate(cfg).envelope_exit.exited);  // the paper's scenario 1 flies
  cfg.plant.actuator.enabled = true;
  Scenario lost = cfg.scenario;
  lost.theta = {{5.0, Vec::Constant(3, 0.1)}, {60.0, Vec::Constant(3, -5.0)}};
  cfg.scenario = lost;
  const SimResult res = test::simulate(cfg);
  ASSERT_TRUE(res.envelope_exit.exited);
  EXPECT_GT(res.envelope_exit.t, 5.0);
  EXPECT_LT(res.envelope_exit.t, 6.0);
  EXPECT_FALSE(res.envelope_exit.non_finite);
  EXPECT_EQ(res.steps, 60000);  // a finite excursion: the run goes on
  EXPECT_EQ(res.envelope_exit.x.size(), 3);
  const double q = std::abs(res.series.x[static_cast<size_t>(res.envelope_exit.step)][2]);
  EXPECT_GT(q, 0.35);  // the recorded sample is the one beyond the bound
  EXPECT_LE(std::abs(res.series.x[static_cast<size_t>(res.envelope_exit.step) - 1][2]), 0.35);

  cfg.plant.actuator.enabled = false;
  cfg.scenario.theta = {{0.5, Vec::Constant(3, 0.1)}, {60.0, Vec::Constant(3, -2000.0)}};
  const SimResult nan_run = test::simulate(cfg);
  ASSERT_TRUE(nan_run.envelope_exit.non_finite);
  EXPECT_LT(nan_run.steps, 60000);
  // The first non-finite number (here the command of step 513, from a theta_hat that
  // overflowed on a state of 1e300) ends the run after that step.
  EXPECT_NEAR(static_cast<double>(nan_run.steps) * 0.001, nan_run.envelope_exit.non_finite_t,
              0.001 + 1e-12);
  for (const Vec& x : nan_run.series.x) ASSERT_TRUE(x.allFinite());  // the controller saw none
}

TEST(EnvelopeMonitor, TimesPrintedForAPerson) {
  // step * dt as the plant computes it: 5004 * 0.001 is 5.0040000000000004
  FlightEnvelope env;
  EnvelopeMonitor m(env, 1);
  PlantConditions c;
  Vec x(3);
  x << 0.0, 0.3, 0.0;
  m.checkState(5004, 5004 * 0.001, x, 0.0, c);
  ASSERT_TRUE(m.exit().exited);
  EXPECT_EQ(m.exit().describe().rfind("t = 5.004 s (step 5004)", 0), 0u) << m.exit().describe();
}
