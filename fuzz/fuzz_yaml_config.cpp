// libFuzzer target: YAML text -> parameter tree -> every section's reader and validation,
// and the same text as a --set value. Anything but a clean ConfigError/FileError is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "preadaptive_mrac/io/setup.hpp"
#include "preadaptive_mrac/io/yaml_params.hpp"

using namespace preadaptive_mrac;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const ParamValue tree = parseYaml(text, "fuzz.yaml");
    Sections all;
    all.strict_top_level = true;
    try {
      const RunConfig cfg = readRunConfig(tree, KeyStyle{}, all);
      // A configuration that validates must also construct and run a few steps.
      Controller ctl(designModelOf(cfg.plant, cfg.controller), cfg.controller);
      ScenarioPlant sim(cfg.plant, cfg.scenario, cfg.controller.sample_time);
      Vec x;
      for (int k = 0; k < 50 && !sim.done(); ++k) {
        x = sim.measured();
        StepInput in;
        in.t = sim.time();
        in.x = &x;
        in.r = sim.reference();
        in.theta_true = &sim.theta();
        sim.advance(ctl.step(in).u);
      }
    } catch (const ConfigError&) {
    }
  } catch (const FileError&) {
  }
  ParamValue t = ParamValue::makeMap();
  try {
    applyOverride(&t, "controller.attention.c_e=" + text);
    applyOverride(&t, text);
  } catch (const FileError&) {
  }
  return 0;
}
