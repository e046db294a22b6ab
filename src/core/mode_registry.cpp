#include "preadaptive_mrac/core/mode_registry.hpp"

#include "preadaptive_mrac/core/l1_law.hpp"
#include "preadaptive_mrac/core/mrac_law.hpp"
#include "preadaptive_mrac/core/oracle_preadaptation.hpp"
#include "preadaptive_mrac/core/paper_preadaptation.hpp"
#include "preadaptive_mrac/core/params.hpp"
#include "preadaptive_mrac/core/robust_preadaptation.hpp"

namespace preadaptive_mrac {

namespace {

template <PaperPreadaptation::Variant V>
std::unique_ptr<PreadaptationStrategy> makePaper(const ModeContext& m) {
  return std::make_unique<PaperPreadaptation>(V, *m.cfg, *m.design, *m.B, *m.PB, m.out, m.net);
}

using P = PaperPreadaptation::Variant;

}  // namespace

const std::vector<ModeEntry>& modeRegistry() {
  // The one list of modes: name, doc, law, strategy. A new mode is a new row.
  static const std::vector<ModeEntry> kModes = {
      {"rac", "regular adaptive control: MRAC, theta_hat never reset", makeMracLaw,
       makePaper<P::kRac>},
      {"pa", "preadaptation: theta_hat := the network's theta_hat_I at each onset, network fixed",
       makeMracLaw, makePaper<P::kPa>},
      {"pa_learn", "preadaptation, the network learning with the approximate gradient (the paper)",
       makeMracLaw, makePaper<P::kPaLearn>},
      {"pa_learn_exact",
       "preadaptation, learning with the exact gradient (needs the true theta: simulation only)",
       makeMracLaw, makePaper<P::kPaLearnExact>},
      {"pa_robust",
       "robust preadaptation: residual trigger, regime memory, verified candidates "
       "(docs/robust.md)",
       makeMracLaw, makeRobustPreadaptation},
      {"oracle", "yardstick: theta_hat := the true theta at each switch (simulation only)",
       makeMracLaw, makeOraclePreadaptation},
      {"l1",
       "L1 adaptive control: state predictor, fast projection-based adaptation, low-pass filtered "
       "adaptive term (docs/l1.md); attention reported as in rac, theta_hat never reset",
       makeL1Law, makePaper<P::kRac>},
  };
  return kModes;
}

const ModeEntry* findMode(const std::string& name) {
  for (const ModeEntry& m : modeRegistry())
    if (name == m.name) return &m;
  return nullptr;
}

void checkModeName(ParamReader& r, const std::string& key, const std::string& name) {
  if (r.usable(key) && findMode(name) == nullptr)
    r.fail(key, "expected one of " + modeNames(", ") + ", got '" + name + "'");
}

std::string modeNames(const std::string& sep, const std::string& last_sep) {
  const std::vector<ModeEntry>& all = modeRegistry();
  std::string s;
  for (size_t i = 0; i < all.size(); ++i) {
    if (i > 0) s += (i + 1 == all.size() && !last_sep.empty()) ? last_sep : sep;
    s += all[i].name;
  }
  return s;
}

std::vector<std::string> modeNameList() {
  std::vector<std::string> v;
  for (const ModeEntry& m : modeRegistry()) v.emplace_back(m.name);
  return v;
}

}  // namespace preadaptive_mrac
