// libFuzzer target: weights-file text -> parseWeights. A file that loads must round-trip.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "preadaptive_mrac/io/weights_io.hpp"

using namespace preadaptive_mrac;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const LearnedState s = parseWeights(text, "fuzz.yaml");
    const LearnedState back = parseWeights(weightsToYaml(s), "roundtrip.yaml");
    if (back.V != s.V || back.W != s.W || back.seed != s.seed || back.episodes != s.episodes)
      std::abort();  // a loadable file must survive save -> load unchanged
    PreadaptNetwork net(s);
    Vec out;
    net.forward(NetInput(0.01, 0.05), &out);
  } catch (const WeightsError&) {
  }
  return 0;
}
