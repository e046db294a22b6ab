/// \file bench_controller.cpp
/// \brief Google Benchmark of the core: Controller::step per mode and a whole scenario 3 per mode.
///
/// Not a test: bench/run_bench.sh runs it with repetitions and writes docs/performance.md.
///
/// ControllerStep/<mode>/trajectory
///   One benchmark iteration = one Controller::step. The inputs (x_k, r_k, theta_true_k) are the
///   samples recorded from a ClosedLoop run of scenario 3 in the same mode, replayed in order
///   from t = 0 to 140 s (and again: at the end of the recording the controller is reset and its
///   network restored to the initial weights). The controller's reference model, estimator,
///   attention and adaptation depend on the measured x only, so the replay reproduces the
///   recorded run exactly: the same onsets, recoveries, theta_hat resets, network updates and
///   sensitivity-ODE phases happen inside the timed loop (checked bit for bit before timing).
///   The iteration count is fixed to whole passes over the recording, so every repetition
///   measures the same mix of quiet and in-phase steps. Reported time = ns per controller step.
/// ControllerStep/<mode>/in_phase
///   Only the steps inside the longest adaptation phase of that recording (for the learning
///   modes every one of them integrates the sensitivity ODE S_dot = Pi S): the controller is
///   replayed untimed up to the onset, copied, and the timed loop steps through the phase and
///   restores the copy at its end. This is the worst steady-state cost per step.
/// PlantStep/rk4
///   One RK4 step of the plant (what ClosedLoop adds per sample).
/// ClosedLoop/scenario3/<mode>
///   ClosedLoop::run over scenario 3 (140 s at dt = 1 ms, 140 000 samples) without recording the
///   time series (what `preadapt_sim --json` does); the network is restored to its initial
///   weights before each run (included in the time; it is a copy of a few dozen doubles).
///   Reported time = ms per run.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "preadaptive_mrac/core/closed_loop.hpp"
#include "preadaptive_mrac/core/controller/controller.hpp"
#include "preadaptive_mrac/core/controller/mode_registry.hpp"
#include "preadaptive_mrac/core/sim/plant.hpp"
#include "preadaptive_mrac/io/setup.hpp"
#include "preadaptive_mrac/io/yaml_params.hpp"

using namespace preadaptive_mrac;

namespace {

constexpr int kPasses = 3;  // whole passes over the 140 000-sample recording per repetition

RunConfig loadConfig(const std::string& scenario, const std::string& mode) {
  ParamValue tree = ParamValue::makeMap();
  tree.merge(loadYamlFile(defaultPlantPath()));
  tree.merge(loadYamlFile(defaultControllerPath()));
  tree.merge(loadYamlFile(scenarioPath(scenario)));
  tree.setPath("controller.mode", ParamValue::makeString(mode));
  return readRunConfig(tree);
}

/// A closed-loop run of one mode, recorded for replay.
struct Recording {
  std::string mode;
  RunConfig cfg;
  LearnedState net0;
  std::vector<double> t, r, u;
  std::vector<Vec> x, theta;
  std::vector<int> phase;  // 1 when a phase is active after the step
  std::vector<std::pair<Event::Type, double>> events;
  size_t onsets = 0, recoveries = 0, learned = 0;
  size_t phase_begin = 0, phase_end = 0;  // longest phase: steps [begin, end) are all in-phase
  size_t steps() const { return t.size(); }
  double inPhaseFraction() const {
    size_t n = 0;
    for (int p : phase) n += static_cast<size_t>(p);
    return t.empty() ? 0.0 : static_cast<double>(n) / static_cast<double>(t.size());
  }
};

StepInput inputAt(const Recording& rec, size_t k) {
  StepInput in;
  in.t = rec.t[k];
  in.x = &rec.x[k];
  in.r = rec.r[k];
  in.theta_true = &rec.theta[k];
  return in;
}

std::unique_ptr<Recording> record(const std::string& mode) {
  auto rec = std::make_unique<Recording>();
  rec->mode = mode;
  rec->cfg = loadConfig("3", mode);
  Controller ctl(designModelOf(rec->cfg.plant, rec->cfg.controller), rec->cfg.controller);
  rec->net0 = ctl.network().state();
  ClosedLoop loop(rec->cfg.plant, rec->cfg.scenario, &ctl);
  SimOptions opt;
  opt.dt = rec->cfg.controller.sample_time;
  opt.record_series = true;
  SimResult res = loop.run(opt);
  const Series& s = res.series;
  rec->t = s.t;
  rec->r = s.r;
  rec->u = s.u;
  rec->x = s.x;
  rec->theta = s.theta_true;
  rec->phase = s.phase;
  for (const Event& e : res.events) {
    rec->events.emplace_back(e.type, e.t);
    rec->onsets += e.type == Event::Type::kOnset;
    rec->recoveries += e.type == Event::Type::kRecovered;
    rec->learned += e.learned;
  }
  // Longest run of in-phase samples after the onset sample itself.
  size_t best = 0;
  for (size_t k = 0; k < rec->phase.size();) {
    if (!rec->phase[k]) {
      ++k;
      continue;
    }
    size_t j = k;
    while (j < rec->phase.size() && rec->phase[j]) ++j;
    // phase[k] = 1 at the onset step; the steady in-phase steps are (k, j).
    if (j - (k + 1) > best) {
      best = j - (k + 1);
      rec->phase_begin = k + 1;
      rec->phase_end = j;
    }
    k = j;
  }
  return rec;
}

/// Replay the whole recording once with a fresh controller and check that it reproduces the
/// closed-loop run (u bit for bit, same events): otherwise the timed replay would not measure
/// what the run did.
std::string verifyReplay(const Recording& rec) {
  Controller ctl(designModelOf(rec.cfg.plant, rec.cfg.controller), rec.cfg.controller);
  size_t ev = 0;
  for (size_t k = 0; k < rec.steps(); ++k) {
    const StepOutput o = ctl.step(inputAt(rec, k));
    if (o.u != rec.u[k])
      return "replay differs from the closed loop at t = " + std::to_string(rec.t[k]);
    if (o.event) {
      if (ev >= rec.events.size() || rec.events[ev].first != o.event->type ||
          rec.events[ev].second != o.event->t)
        return "replay event differs at t = " + std::to_string(o.event->t);
      ++ev;
    }
  }
  if (ev != rec.events.size()) return "replay missed events";
  return "";
}

void setCounters(benchmark::State& state, const Recording& rec) {
  state.counters["onsets/pass"] = static_cast<double>(rec.onsets);
  state.counters["learned/pass"] = static_cast<double>(rec.learned);
  state.counters["in_phase_%"] = 100.0 * rec.inPhaseFraction();
}

void BM_ControllerStepTrajectory(benchmark::State& state, const Recording* rec) {
  Controller ctl(designModelOf(rec->cfg.plant, rec->cfg.controller), rec->cfg.controller);
  const size_t n = rec->steps();
  size_t k = 0;
  for (auto _ : state) {
    if (k == n) {  // next pass: back to t = 0 with the initial weights
      ctl.reset();
      ctl.setNetwork(rec->net0);
      k = 0;
    }
    StepOutput o = ctl.step(inputAt(*rec, k));
    benchmark::DoNotOptimize(o);
    ++k;
  }
  setCounters(state, *rec);
}

void BM_ControllerStepInPhase(benchmark::State& state, const Recording* rec) {
  Controller ctl(designModelOf(rec->cfg.plant, rec->cfg.controller), rec->cfg.controller);
  for (size_t k = 0; k < rec->phase_begin; ++k) ctl.step(inputAt(*rec, k));
  if (!ctl.phaseActive()) {
    state.SkipWithError("no adaptation phase at the replayed onset");
    return;
  }
  const Controller at_onset = ctl;
  size_t k = rec->phase_begin;
  for (auto _ : state) {
    if (k == rec->phase_end) {
      ctl = at_onset;
      k = rec->phase_begin;
    }
    StepOutput o = ctl.step(inputAt(*rec, k));
    benchmark::DoNotOptimize(o);
    ++k;
  }
  state.counters["phase_steps"] = static_cast<double>(rec->phase_end - rec->phase_begin);
  state.counters["phase_t0_s"] = rec->t[rec->phase_begin];
}

void BM_PlantStep(benchmark::State& state, const Recording* rec) {
  Plant plant(rec->cfg.plant);
  const double dt = rec->cfg.controller.sample_time;
  size_t k = 0;
  for (auto _ : state) {
    if (k == rec->steps()) k = 0;
    plant.setState(rec->x[k]);
    plant.step(dt, rec->theta[k], rec->u[k], rec->r[k]);
    benchmark::DoNotOptimize(plant.state().data());
    ++k;
  }
}

// The plant simulator's step (ScenarioPlant::advance: actuator chain, effectiveness, gust, RK4,
// next sample's inputs) on scenario 3 with the recorded commands, with the issue-20 parts off
// (the paper's plant) and on, one by one and all together.
enum class Parts { kOff, kLimits, kDelayLag, kEffectiveness, kTurbulence, kAll };

void BM_ScenarioPlantStep(benchmark::State& state, const Recording* rec, Parts parts) {
  PlantConfig plant = rec->cfg.plant;
  Scenario scenario = rec->cfg.scenario;
  const bool all = parts == Parts::kAll;
  if (all || parts == Parts::kLimits) {
    plant.actuator.enabled = true;
    plant.actuator.max_deflection = 0.4363;
    plant.actuator.max_rate = 1.0472;
  }
  if (all || parts == Parts::kDelayLag) {
    plant.dynamics.delay = 0.05;
    plant.dynamics.time_constant = 0.05;
  }
  if (all || parts == Parts::kEffectiveness)
    scenario.effectiveness = {{20.0, 1.0}, {scenario.endTime(), 0.5}};
  if (all || parts == Parts::kTurbulence) {
    plant.turbulence.enabled = true;
    plant.turbulence.sigma_w = 1.5;
    plant.turbulence.length_scale = 533.4;
  }
  ScenarioPlant sim(plant, scenario, rec->cfg.controller.sample_time);
  size_t k = 0;
  for (auto _ : state) {
    if (sim.done()) {
      sim.reset();
      k = 0;
    }
    sim.advance(rec->u[k++]);
    benchmark::DoNotOptimize(sim.state().data());
  }
}

void BM_ClosedLoopScenario3(benchmark::State& state, const Recording* rec) {
  Controller ctl(designModelOf(rec->cfg.plant, rec->cfg.controller), rec->cfg.controller);
  ClosedLoop loop(rec->cfg.plant, rec->cfg.scenario, &ctl);
  SimOptions opt;
  opt.dt = rec->cfg.controller.sample_time;
  opt.record_series = false;
  std::int64_t steps = 0;
  for (auto _ : state) {
    ctl.setNetwork(rec->net0);
    SimResult res = loop.run(opt);
    steps = res.steps;
    benchmark::DoNotOptimize(res.metrics.iae);
  }
  state.counters["steps"] = static_cast<double>(steps);
  // CPU seconds per sample (Google Benchmark divides rates by the CPU time).
  state.counters["per_step"] =
      benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kIsIterationInvariantRate |
                                                         benchmark::Counter::kInvert);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;

  std::vector<std::unique_ptr<Recording>> recs;
  try {
    for (const std::string& m : modeNameList()) {
      recs.push_back(record(m));
      const std::string err = verifyReplay(*recs.back());
      if (!err.empty()) {
        std::fprintf(stderr, "bench_controller: %s: %s\n", m.c_str(), err.c_str());
        return 1;
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_controller: set-up failed: %s\n", e.what());
    return 1;
  }

  for (const auto& rec : recs) {
    const std::string m = rec->mode;
    benchmark::RegisterBenchmark(("ControllerStep/" + m + "/trajectory").c_str(),
                                 BM_ControllerStepTrajectory, rec.get())
        ->Iterations(static_cast<benchmark::IterationCount>(kPasses * rec->steps()))
        ->Unit(benchmark::kNanosecond);
  }
  for (const auto& rec : recs) {
    const std::string m = rec->mode;
    const size_t len = rec->phase_end - rec->phase_begin;
    benchmark::RegisterBenchmark(("ControllerStep/" + m + "/in_phase").c_str(),
                                 BM_ControllerStepInPhase, rec.get())
        ->Iterations(static_cast<benchmark::IterationCount>(
            std::max<size_t>(1, len) * std::max<size_t>(1, 400000 / std::max<size_t>(1, len))))
        ->Unit(benchmark::kNanosecond);
  }
  benchmark::RegisterBenchmark("PlantStep/rk4", BM_PlantStep, recs.front().get())
      ->Unit(benchmark::kNanosecond);
  const std::pair<const char*, Parts> parts[] = {{"off", Parts::kOff},
                                                 {"limits", Parts::kLimits},
                                                 {"delay_lag", Parts::kDelayLag},
                                                 {"effectiveness", Parts::kEffectiveness},
                                                 {"turbulence", Parts::kTurbulence},
                                                 {"all", Parts::kAll}};
  for (const auto& [name, p] : parts)
    benchmark::RegisterBenchmark((std::string("ScenarioPlantStep/") + name).c_str(),
                                 BM_ScenarioPlantStep, recs.front().get(), p)
        ->Unit(benchmark::kNanosecond);
  for (const auto& rec : recs) {
    const std::string m = rec->mode;
    benchmark::RegisterBenchmark(("ClosedLoop/scenario3/" + m).c_str(), BM_ClosedLoopScenario3,
                                 rec.get())
        ->Unit(benchmark::kMillisecond);
  }

  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
