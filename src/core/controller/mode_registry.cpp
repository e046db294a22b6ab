#include "preadaptive_mrac/core/controller/mode_registry.hpp"

#include <stdexcept>

#include "preadaptive_mrac/core/control/design_model.hpp"
#include "preadaptive_mrac/core/control/l1/l1_law.hpp"
#include "preadaptive_mrac/core/control/mrac/mrac_law.hpp"
#include "preadaptive_mrac/core/control/oracle/oracle_preadaptation.hpp"
#include "preadaptive_mrac/core/control/paper/paper_preadaptation.hpp"
#include "preadaptive_mrac/core/robust/robust_preadaptation.hpp"
#include "preadaptive_mrac/core/schema/params.hpp"
#include "preadaptive_mrac/params/modes_params.hpp"

namespace preadaptive_mrac {

namespace {

template <PaperPreadaptation::Variant V>
std::unique_ptr<PreadaptationStrategy> makePaper(const ModeContext& m) {
  return std::make_unique<PaperPreadaptation>(V, *m.cfg, *m.design, *m.B, *m.PB,
                                              m.model->output_index, m.net);
}

using P = PaperPreadaptation::Variant;

template <class Entry>
auto findPart(const std::vector<Entry>& parts, const char* name) -> decltype(parts[0].make) {
  for (const Entry& e : parts)
    if (std::string(name) == e.name) return e.make;
  return nullptr;
}

}  // namespace

// The registered parts, by the names params/modes.yaml gives them. A new law or strategy is one
// row here; a new mode that combines registered parts is one row of the table only.
const std::vector<LawEntry>& lawRegistry() {
  static const std::vector<LawEntry> kLaws = {{"mrac", makeMracLaw}, {"l1", makeL1Law}};
  return kLaws;
}

const std::vector<StrategyEntry>& strategyRegistry() {
  static const std::vector<StrategyEntry> kStrategies = {
      {"paper_rac", makePaper<P::kRac>},
      {"paper_pa", makePaper<P::kPa>},
      {"paper_pa_learn", makePaper<P::kPaLearn>},
      {"paper_pa_learn_exact", makePaper<P::kPaLearnExact>},
      {"robust", makeRobustPreadaptation},
      {"oracle", makeOraclePreadaptation},
  };
  return kStrategies;
}

const std::vector<ModeEntry>& modeRegistry() {
  // The one list of modes is params/modes.yaml (generated into params::kModeRows); each row's
  // law and strategy are looked up by name. A name no part registers is a programming error
  // of the table, caught the first time any mode is asked for (and by test_config,
  // ModeRegistry.EveryTableRowIsARegisteredLawAndStrategy).
  static const std::vector<ModeEntry> kModes = [] {
    std::vector<ModeEntry> v;
    for (const params::ModeRow& row : params::kModeRows) {
      const auto law = findPart(lawRegistry(), row.law);
      const auto strategy = findPart(strategyRegistry(), row.strategy);
      if (law == nullptr || strategy == nullptr)
        throw std::logic_error(std::string("params/modes.yaml: mode '") + row.name + "' names " +
                               (law == nullptr ? "law '" : "strategy '") +
                               (law == nullptr ? row.law : row.strategy) +
                               "', which src/core/controller/mode_registry.cpp does not register");
      v.push_back({row.name, row.doc, law, strategy, row.truth});
    }
    return v;
  }();
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
