/// \file bench_jsbsim.cpp
/// \brief Per-step cost of the plant engines: ScenarioPlant::advance on the
/// linear model and on JSBSim (the whole coupling: set + iterate, the completed-step read,
/// e_I), and the bare socket round trips under it. Medians of repeated blocks, one sitting.
///   flock /work/bench.lock build/devel/lib/preadaptive_mrac/bench_jsbsim [steps] [repeats]
/// Needs JSBSim (scripts/install_jsbsim); run from the source checkout (config/ and jsbsim/).

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "preadaptive_mrac/core/sim/scenario_plant.hpp"
#include "preadaptive_mrac/io/setup.hpp"
#include "preadaptive_mrac/io/yaml_params.hpp"
#include "preadaptive_mrac/jsbsim/jsbsim_plant.hpp"

using namespace preadaptive_mrac;
using Clock = std::chrono::steady_clock;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// Times this thread has slept (voluntary context switches): each wait for JSBSim's answer
/// that found nothing there yet is one.
long sleeps() {
  rusage u{};
  ::getrusage(RUSAGE_THREAD, &u);
  return u.ru_nvcsw;
}

/// A block's cost: microseconds and sleeps of the stepping thread, per step.
struct Cost {
  double us, sleeps;
};

Cost medianCost(const std::vector<Cost>& c) {
  std::vector<double> us, sl;
  for (const Cost& x : c) {
    us.push_back(x.us);
    sl.push_back(x.sleeps);
  }
  return {median(us), median(sl)};
}

RunConfig loadScenario1() {
  ParamValue tree = ParamValue::makeMap();
  tree.merge(loadYamlFile(defaultPlantPath()));
  tree.merge(loadYamlFile(defaultControllerPath()));
  tree.merge(loadYamlFile(scenarioPath("1")));
  Sections sections;
  return readRunConfig(tree, KeyStyle{}, sections);
}

/// Microseconds per ScenarioPlant::advance over `steps` steps (a 0.01 rad elevator square
/// wave of 1 Hz), median of `repeats` blocks.
Cost plantStepUs(const PlantConfig& plant, const Scenario& sc, int steps, int repeats) {
  ScenarioPlant sim(plant, sc, 0.001);
  std::vector<Cost> c;
  for (int r = 0; r < repeats; ++r) {
    const long s0 = sleeps();
    const auto t0 = Clock::now();
    for (int k = 0; k < steps; ++k) sim.advance(((k / 500) % 2 ? 0.01 : -0.01));
    c.push_back({std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / steps,
                 static_cast<double>(sleeps() - s0) / steps});
  }
  return medianCost(c);
}

/// Microseconds per bare protocol exchange on a trimmed JSBSim: `packet` of `lines` commands,
/// then `output_lines` lines of the output socket.
Cost exchangeUs(JsbsimProcess& p, const std::string& packet, size_t lines, int output_lines,
                int steps, int repeats) {
  std::vector<Cost> c;
  for (int r = 0; r < repeats; ++r) {
    const long s0 = sleeps();
    const auto t0 = Clock::now();
    for (int k = 0; k < steps; ++k) {
      p.send(packet);
      for (int i = 0; i < output_lines; ++i) p.readOutput();
      p.replies(lines);
    }
    c.push_back({std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / steps,
                 static_cast<double>(sleeps() - s0) / steps});
  }
  return medianCost(c);
}

}  // namespace

int main(int argc, char** argv) {
  const int steps = argc > 1 ? std::atoi(argv[1]) : 2000;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 5;
  try {
    RunConfig rc = loadScenario1();
    const Cost lin = plantStepUs(rc.plant, rc.scenario, steps * 50, repeats);
    PlantConfig js = rc.plant;
    js.engine = PlantEngineKind::kJsbsim;
    const Cost jsb = plantStepUs(js, rc.scenario, steps, repeats);
    JsbsimPlant raw(js.jsbsim, 0.001, 0.0);
    raw.reset();
    auto& p = raw.process();
    // (`iterate 1`: the output lines of the pass that takes it in and of the step)
    const Cost iter = exchangeUs(p, "iterate 1\n", 1, 2, steps, repeats);
    const Cost get1 = exchangeUs(p, "get simulation/frame\n", 1, 0, steps, repeats);
    std::printf("per-step cost, median of %d blocks:                us   sleeps\n", repeats);
    std::printf("  ScenarioPlant::advance, linear (RK4)          %10.3f %8.2f\n", lin.us,
                lin.sleeps);
    std::printf("  ScenarioPlant::advance, jsbsim (coupling)     %10.3f %8.2f  (%.0fx linear)\n",
                jsb.us, jsb.sleeps, jsb.us / lin.us);
    std::printf("  socket: 'iterate 1' and its 2 output lines    %10.3f %8.2f\n", iter.us,
                iter.sleeps);
    std::printf("  socket: 1 get                                 %10.3f %8.2f\n", get1.us,
                get1.sleeps);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_jsbsim: %s\n", e.what());
    return 1;
  }
  return 0;
}
