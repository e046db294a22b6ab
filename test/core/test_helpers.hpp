#pragma once
// Shared set-up for the core tests: the package's YAML files, read as the CLI reads them.

#include <string>

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

}  // namespace test
}  // namespace preadaptive_mrac
