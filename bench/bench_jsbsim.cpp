/// \file bench_jsbsim.cpp
/// \brief Per-step cost of the plant engines: ScenarioPlant::advance on the
/// linear model and on JSBSim (the whole coupling: set + iterate, the completed-step read,
/// e_I), and the bare socket round trips under it. Medians of repeated blocks, one sitting.
///   flock /work/bench.lock build/devel/lib/preadaptive_mrac/bench_jsbsim [steps] [repeats]
/// Needs JSBSim (scripts/install_jsbsim); run from the source checkout (config/ and jsbsim/).

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
double plantStepUs(const PlantConfig& plant, const Scenario& sc, int steps, int repeats) {
  ScenarioPlant sim(plant, sc, 0.001);
  std::vector<double> us;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = Clock::now();
    for (int k = 0; k < steps; ++k) sim.advance(((k / 500) % 2 ? 0.01 : -0.01));
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / steps);
  }
  if (const auto* j = dynamic_cast<const JsbsimPlant*>(sim.engine()))
    std::printf("  (jsbsim: %lld of %d steps read with the step itself, %lld reads repeated)\n",
                static_cast<long long>(j->earlyReads()), steps * repeats,
                static_cast<long long>(j->rereads()));
  return median(us);
}

/// Microseconds per bare protocol exchange on a trimmed JSBSim: `packet` of `lines` commands.
double exchangeUs(JsbsimProcess& p, const std::string& packet, size_t lines, int steps,
                  int repeats) {
  std::vector<double> us;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = Clock::now();
    for (int k = 0; k < steps; ++k) p.transact(packet, lines);
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / steps);
  }
  return median(us);
}

}  // namespace

int main(int argc, char** argv) {
  const int steps = argc > 1 ? std::atoi(argv[1]) : 2000;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 5;
  try {
    RunConfig rc = loadScenario1();
    const double lin = plantStepUs(rc.plant, rc.scenario, steps * 50, repeats);
    PlantConfig js = rc.plant;
    js.engine = PlantEngineKind::kJsbsim;
    const double jsb = plantStepUs(js, rc.scenario, steps, repeats);
    JsbsimPlant raw(js.jsbsim, 0.001, 0.0);
    raw.reset();
    auto& p = raw.process();
    const double iter = exchangeUs(p, "iterate 1\nget simulation/frame\n", 2, steps, repeats);
    const double get1 = exchangeUs(p, "get simulation/frame\n", 1, steps, repeats);
    const double get7 =
        exchangeUs(p,
                   "get pmrac/sync/frame\nget pmrac/dev/theta-rad\n"
                   "get pmrac/dev/gamma-rad\nget pmrac/dev/q-rad_sec\nget pmrac/dev/vt-fps\n"
                   "get pmrac/dev/h-sl-ft\n",
                   6, steps, repeats);
    std::printf("per-step cost, median of %d blocks (us):\n", repeats);
    std::printf("  ScenarioPlant::advance, linear (RK4)          %10.3f\n", lin);
    std::printf("  ScenarioPlant::advance, jsbsim (coupling)     %10.3f  (%.0fx linear)\n", jsb,
                jsb / lin);
    std::printf("  socket: 'iterate 1' + 1 get in one packet     %10.3f\n", iter);
    std::printf("  socket: 1 get                                 %10.3f\n", get1);
    std::printf("  socket: 6 gets in one packet (the step read)  %10.3f\n", get7);
    std::printf("  jsbsim reads repeated (mid-step)               %lld\n",
                static_cast<long long>(raw.rereads()));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_jsbsim: %s\n", e.what());
    return 1;
  }
  return 0;
}
