/// \file family_draw.cpp
/// \brief preadapt_family's draw: the files validated against the flags, then each scenario, its
/// plant conditions and its runs (one per mode, the same noise and gust for every mode).

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "family_tool.hpp"
#include "preadaptive_mrac/io/yaml_params.hpp"

namespace preadaptive_mrac {
namespace family {
namespace {

// A value drawn of `key`, taken into the span of the family.
void widen(Span* span, const std::string& key, double v) {
  auto it = span->emplace(key, std::make_pair(v, v)).first;
  it->second = {std::min(it->second.first, v), std::max(it->second.second, v)};
}

// Feasible regimes: only with elevator limits (without, or with every_regime, every regime
// drawn is flown: no check).
std::optional<TrimCheck> trimCheck(const Options& opt, const FamilySpec& spec,
                                   const RunConfig& cfg) {
  const ActuatorLimits& limits = cfg.plant.actuator;
  if (!limits.enabled || opt.every_regime) return std::nullopt;
  // The controller's design model where it has one (its reference model), else the plant.
  const auto& model = cfg.controller.model;
  const auto& pl = cfg.plant;
  const Eigen::RowVectorXd K = cfg.design ? cfg.design->K : Eigen::RowVectorXd();
  if (K.size() != spec.n) return std::nullopt;
  const double r_max = spec.ref_every > 0.0 ? std::max(std::abs(spec.r_min), std::abs(spec.r_max))
                                            : std::abs(spec.r);
  return makeTrimCheck(model.A.size() ? model.A : pl.A, model.B.size() ? model.B : pl.B,
                       model.B1r.size() ? model.B1r : pl.B1r, K, r_max,
                       opt.trim_fraction * limits.max_deflection);
}

// What one scenario drew for its runs besides its theta schedule.
struct ScenarioDraws {
  std::optional<double> delay, lag, gust;
  std::optional<PlantMismatch> truth;  ///< the true plant (--mismatch)
};

// Lambda over the scenario: one value, or one per regime (recorded in `d` and the span).
void drawEffectiveness(const Options& opt, int k, Scenario* sc, nlohmann::ordered_json* d,
                       Span* span) {
  if (opt.lambda) sc->effectiveness = {{sc->endTime(), *opt.lambda}};
  if (!opt.lambda_range.drawn()) return;
  sc->effectiveness = regimeEffectiveness(*sc, opt.lambda_range, opt.seed, k);
  auto& list = (*d)["effectiveness"] = nlohmann::ordered_json::array();
  for (const auto& seg : sc->effectiveness) {
    list.push_back(seg.value);
    if (seg.until == sc->theta.front().until) continue;  // the first segment's 1
    widen(span, "effectiveness", seg.value);
  }
}

// The physical faults per regime (recorded in `d` and the span).
void drawFaults(const Options& opt, int k, Scenario* sc, nlohmann::ordered_json* d, Span* span) {
  sc->faults = regimeFaults(*sc, *opt.faults, opt.seed, k);
  auto& list = (*d)["faults"] = nlohmann::ordered_json::array();
  for (size_t i = 0; i < sc->faults.size(); ++i) {
    auto& seg = list.emplace_back(nlohmann::ordered_json::object());
    for (const auto& key : Scenario::kFaultKeys) {
      const double v = sc->faults[i].*key.field;
      seg[key.name] = v;
      if (i == 0) continue;  // the first segment's nominal aircraft
      widen(span, std::string("fault ") + key.name, v);
    }
  }
}

// A condition drawn per scenario (none when its range is one value or not given).
std::optional<double> drawOne(const Options& opt, int k, const ConditionRange& r,
                              std::uint64_t stream, const std::string& key,
                              nlohmann::ordered_json* d, Span* span) {
  if (!r.drawn()) return std::nullopt;
  const double v = drawCondition(r, opt.seed, k, stream);
  (*d)[key] = v;
  widen(span, key, v);
  return v;
}

// The true plant: drawn from a stream of its own, so no other value of the family moves.
std::optional<PlantMismatch> drawMismatch(const Options& opt, int k, const PlantConfig& plant,
                                          nlohmann::ordered_json* d, Span* span) {
  if (!opt.mismatch) return std::nullopt;
  PlantMismatch truth = mismatchedPlant(plant.A, plant.B, *opt.mismatch, opt.seed, k);
  if (*opt.mismatch > 0.0) {
    (*d)["plant.A"] = nlohmann::ordered_json::array();
    for (Eigen::Index i = 0; i < truth.A.rows(); ++i) {
      auto row = nlohmann::ordered_json::array();
      for (Eigen::Index j = 0; j < truth.A.cols(); ++j) row.push_back(truth.A(i, j));
      (*d)["plant.A"].push_back(row);
    }
    (*d)["plant.B"] = nlohmann::ordered_json::array();
    for (Eigen::Index i = 0; i < truth.B.size(); ++i) (*d)["plant.B"].push_back(truth.B[i]);
    (*d)["mismatch_factors"] = truth.factors;
    for (const double f : truth.factors) widen(span, "mismatch factor", f);
  }
  return truth;
}

// Scenario k's runs, one per mode, on the scenario and its draws.
void addJobs(const Options& opt, const FamilySpec& spec, const RunConfig& base, int k,
             const Scenario& sc, const ScenarioDraws& draws, std::vector<Job>* jobs) {
  const std::uint64_t noise_seed = opt.seed * 1000003ULL + static_cast<std::uint64_t>(k);
  for (const auto& m : opt.modes) {
    Job job;
    job.scenario = k;
    job.mode = m;
    job.cfg = base;
    job.cfg.scenario = sc;
    job.cfg.controller.mode = m;
    if (opt.noise > 0.0) {
      job.cfg.plant.noise.std = Eigen::VectorXd::Zero(spec.n);
      for (int i = 1; i < spec.n; ++i) job.cfg.plant.noise.std[i] = opt.noise;
      job.cfg.plant.noise.seed = noise_seed;
      deriveAttention(&job.cfg);  // derived thresholds see this noise (more noise: a larger c_e)
    } else if (job.cfg.plant.noise.active()) {
      // Noise through --set plant.noise.std: a noise of its own per scenario as well, the
      // same for every mode (paired comparison).
      job.cfg.plant.noise.seed = noise_seed;
    }
    if (draws.delay) job.cfg.plant.dynamics.delay = *draws.delay;
    if (draws.lag) job.cfg.plant.dynamics.time_constant = *draws.lag;
    if (draws.gust) job.cfg.plant.turbulence.sigma_w = *draws.gust;
    if (draws.truth) {
      // The controller designs on the nominal plant, the run is on the true one.
      job.cfg.controller.model.A = base.plant.A;
      job.cfg.controller.model.B = base.plant.B;
      job.cfg.controller.model.B1r = base.plant.B1r;
      job.cfg.plant.A = draws.truth->A;
      job.cfg.plant.B = draws.truth->B;
    }
    // A gust of its own per scenario, the same for every mode (paired comparison).
    if (opt.turbulence)
      job.cfg.plant.turbulence.seed = opt.seed * 1000033ULL + static_cast<std::uint64_t>(k);
    jobs->push_back(std::move(job));
  }
}

// Scenario k: its theta schedule, its conditions, its file (--out-dir) and its runs.
void drawScenario(const Options& opt, const FamilySpec& spec, int k, Family* fam) {
  auto& d = fam->drawn[static_cast<size_t>(k)];
  Scenario sc =
      recurringScenario(spec, opt.seed, k, fam->trim ? &*fam->trim : nullptr, &fam->rejected);
  drawEffectiveness(opt, k, &sc, &d, &fam->span);
  if (opt.faults) drawFaults(opt, k, &sc, &d, &fam->span);
  ScenarioDraws draws;
  draws.delay = drawOne(opt, k, opt.delay, 1, "plant.actuator.delay", &d, &fam->span);
  draws.lag = drawOne(opt, k, opt.lag, 2, "plant.actuator.time_constant", &d, &fam->span);
  draws.gust = drawOne(opt, k, opt.gust, 3, "plant.turbulence.sigma_w", &d, &fam->span);
  fam->repeated.push_back(repeatedWindows(sc));
  draws.truth = drawMismatch(opt, k, fam->prepared.cfg.plant, &d, &fam->span);
  if (!opt.out_dir.empty()) {
    std::ofstream f(opt.out_dir + "/scenario_" + std::to_string(k) + ".yaml");
    f << scenarioToYaml(sc);
    if (!f) throw cli::UsageError("--out-dir: cannot write into '" + opt.out_dir + "'");
  }
  addJobs(opt, spec, fam->prepared.cfg, k, sc, draws, &fam->jobs);
}
}  // namespace

Family drawFamily(const Options& opt) {
  Family fam;
  // Validate the files and overrides once, through the same path as preadapt_sim.
  cli::RunRequest probe = opt.base;
  probe.scenario = "1";
  fam.prepared = cli::prepare(probe);
  const RunConfig& cfg = fam.prepared.cfg;
  FamilySpec spec = opt.spec;
  spec.n = cfg.plant.n();
  if (opt.mismatch && (spec.n < 3 || cfg.plant.output_index != 1))
    throw cli::UsageError("--mismatch: needs the plant's x = [e_I, alpha, q] (output_index 1)");
  if (opt.faults && !plantEngineRules(cfg.plant.engine).physical_faults)
    throw cli::UsageError(std::string("--faults: ") + kFaultsNeedAerodynamics +
                          " (add --set plant.engine=jsbsim); the linear model has no CG or "
                          "aerodynamics (use --effectiveness on it)");
  if (!opt.out_dir.empty()) {
    // An earlier family's results are not replaced without being asked to.
    std::error_code ec;
    for (const char* name : {"runs.jsonl", "scenario_0.yaml"})
      if (!opt.force && std::filesystem::exists(opt.out_dir + "/" + name, ec))
        throw cli::UsageError("--out-dir: '" + opt.out_dir + "' holds an earlier family (" + name +
                              "): not replaced (name a new folder, or --force)");
    ::mkdir(opt.out_dir.c_str(), 0755);
  }
  fam.trim = trimCheck(opt, spec, cfg);
  // What each scenario drew (runs.jsonl's drawn_conditions), and the span over the family.
  fam.drawn.resize(static_cast<size_t>(opt.count));
  for (int k = 0; k < opt.count; ++k) drawScenario(opt, spec, k, &fam);
  return fam;
}

}  // namespace family
}  // namespace preadaptive_mrac
