// libFuzzer target: arbitrary bytes as incoming state messages (size and doubles, NaN and Inf
// included) through the InputGuard the nodes use, then into the controller when accepted.
// Invariant: the controller only ever sees finite samples of the right size.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "preadaptive_mrac/core/control/input_guard.hpp"
#include "preadaptive_mrac/io/setup.hpp"
#include "preadaptive_mrac/io/yaml_params.hpp"

using namespace preadaptive_mrac;

namespace {
struct Fixture {
  RunConfig cfg;
  std::unique_ptr<Controller> ctl;
  Fixture() {
    ParamValue tree = ParamValue::makeMap();
    tree.merge(loadYamlFile(defaultPlantPath()));
    tree.merge(loadYamlFile(defaultControllerPath()));
    tree.merge(loadYamlFile(scenarioPath("1")));
    cfg = readRunConfig(tree);
    ctl = std::make_unique<Controller>(designModelOf(cfg.plant, cfg.controller), cfg.controller);
  }
};
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Fixture fx;
  fx.ctl->reset();
  InputGuard guard(3, 0.05);
  size_t off = 0;
  double t = 0.0;
  while (off < size) {
    const size_t n = data[off++] % 6;  // message sizes 0..5 around the expected 3
    std::vector<double> x(n);
    for (size_t i = 0; i < n && off + sizeof(double) <= size; ++i, off += sizeof(double))
      std::memcpy(&x[i], data + off, sizeof(double));
    t += 0.001;
    if (guard.accept(t, x.data(), x.size())) {
      Vec xs(3);
      for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(x[static_cast<size_t>(i)])) std::abort();  // guard let a bad one in
        xs[i] = x[static_cast<size_t>(i)];
      }
      StepInput in;
      in.t = t;
      in.x = &xs;
      in.r = 0.1;
      (void)fx.ctl->step(in);
    } else if (!guard.lastRejection().empty() && guard.stale(t + 1.0)) {
      (void)fx.ctl->safeCommand(Vec::Zero(3), StalePolicy::kBaselineHold);
    }
  }
  return 0;
}
