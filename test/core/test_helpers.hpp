#pragma once
// Shared set-up for the core tests: the package's YAML files, read as the CLI reads them.

#include <string>

#include "preadaptive_mrac/core/closed_loop.hpp"
#include "preadaptive_mrac/io/setup.hpp"
#include "preadaptive_mrac/io/yaml_params.hpp"

namespace preadaptive_mrac {
namespace test {

inline ParamValue packageTree(const std::string& scenario = "1") {
  ParamValue tree = ParamValue::makeMap();
  tree.merge(loadYamlFile(defaultPlantPath()));
  tree.merge(loadYamlFile(defaultControllerPath()));
  tree.merge(loadYamlFile(scenarioPath(scenario)));
  return tree;
}

inline RunConfig packageConfig(const std::string& scenario = "1") {
  return readRunConfig(packageTree(scenario));
}

/// \brief cfg's closed loop in the batch simulator at the controller's sample time, with the
/// time series.
inline SimResult simulate(const RunConfig& cfg) {
  Controller ctl(designModelOf(cfg.plant, cfg.controller), cfg.controller);
  ClosedLoop loop(cfg.plant, cfg.scenario, &ctl);
  SimOptions opt;
  opt.dt = cfg.controller.sample_time;
  opt.record_series = true;
  return loop.run(opt);
}

/// \brief The controller's input at the plant's current sample, as the batch loop builds it;
/// `u_applied` (may be null: a plant that reports no surface position) must outlive the step.
inline StepInput lockstepInput(const ScenarioPlant& plant, const double* u_applied) {
  StepInput in;
  in.t = plant.time();
  in.x = &plant.measured();
  in.r = plant.reference();
  in.theta_true = &plant.theta();
  in.u_applied = u_applied;
  return in;
}

}  // namespace test
}  // namespace preadaptive_mrac
