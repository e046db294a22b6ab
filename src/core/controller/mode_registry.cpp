#include "preadaptive_mrac/core/controller/mode_registry.hpp"

#include <deque>
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

// The built-in parts, registered as a new part is (control/part_registry.hpp), in this order,
// by the names params/modes.yaml gives them. Rows here rather than a line in each part's folder:
// one place fixes their order and names, and a program that uses modes links this file, so no
// built-in part can be left out of a static link. Once: a static initialiser below, and every
// read of the modes first (whichever runs first).
bool builtInPartsRegistered() {
  static const bool kDone = [] {
    registerLaw("mrac", makeMracLaw);
    registerLaw("l1", makeL1Law);
    registerStrategy("paper_rac", makePaper<P::kRac>);
    registerStrategy("paper_pa", makePaper<P::kPa>);
    registerStrategy("paper_pa_learn", makePaper<P::kPaLearn>);
    registerStrategy("paper_pa_learn_exact", makePaper<P::kPaLearnExact>);
    registerStrategy("robust", makeRobustPreadaptation);
    registerStrategy("oracle", makeOraclePreadaptation);
    return true;
  }();
  return kDone;
}
const bool kBuiltInParts = builtInPartsRegistered();

// The modes registered at run time, until the table's rows are put in front of them (the first
// read of modeRegistry()), and all of them after. Function-local: modes register from static
// initialisers too.
std::deque<ModeEntry>& modes() {
  static std::deque<ModeEntry> all;
  return all;
}

// A registered mode's name and doc, where its entry's `const char*` point (a deque never moves
// them).
struct ModeText {
  std::string name, doc;
};
std::deque<ModeText>& modeTexts() {
  static std::deque<ModeText> all;
  return all;
}

bool inTable(const std::string& name) {
  for (const params::ModeRow& row : params::kModeRows)
    if (name == row.name) return true;
  return false;
}

}  // namespace

bool registerMode(const std::string& name, const std::string& doc, const std::string& law,
                  const std::string& strategy, bool truth) {
  (void)builtInPartsRegistered();
  const std::string what = "registerMode: mode '" + name + "'";
  if (name.empty()) throw std::logic_error("registerMode: an empty name");
  bool taken = inTable(name);
  for (const ModeEntry& m : modes()) taken = taken || name == m.name;
  if (taken) throw std::logic_error(what + " exists already");
  const LawFactory make_law = findLaw(law);
  if (make_law == nullptr)
    throw std::logic_error(what + " names law '" + law + "', not registered");
  const StrategyFactory make_strategy = findStrategy(strategy);
  if (make_strategy == nullptr)
    throw std::logic_error(what + " names strategy '" + strategy + "', not registered");
  const ModeText& text = modeTexts().emplace_back(ModeText{name, doc});
  modes().push_back({text.name.c_str(), text.doc.c_str(), make_law, make_strategy, truth});
  return true;
}

const std::deque<ModeEntry>& modeRegistry() {
  // The one list of modes users see is params/modes.yaml (generated into params::kModeRows);
  // each row's law and strategy are looked up by name, once, on the first read (after the
  // static initialisers that register parts). A name no part registers is a programming error
  // of the table, caught the first time any mode is asked for (and by test_config,
  // ModeRegistry.EveryTableRowIsARegisteredLawAndStrategy).
  static const bool kTableRead = [] {
    (void)builtInPartsRegistered();
    std::vector<ModeEntry> table;
    for (const params::ModeRow& row : params::kModeRows) {
      const LawFactory law = findLaw(row.law);
      const StrategyFactory strategy = findStrategy(row.strategy);
      if (law == nullptr || strategy == nullptr)
        throw std::logic_error(std::string("params/modes.yaml: mode '") + row.name + "' names " +
                               (law == nullptr ? "law '" : "strategy '") +
                               (law == nullptr ? row.law : row.strategy) +
                               "', which no part registers (control/part_registry.hpp)");
      table.push_back({row.name, row.doc, law, strategy, row.truth});
    }
    // At the front: references to the modes registered before stay valid (a deque's ends).
    modes().insert(modes().begin(), table.begin(), table.end());
    return true;
  }();
  (void)kTableRead;
  return modes();
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
  const std::deque<ModeEntry>& all = modeRegistry();
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
