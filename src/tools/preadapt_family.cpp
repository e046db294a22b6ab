/// \file preadapt_family.cpp
/// \brief Families of random recurring-regime scenarios: write them, run rac and the chosen
/// modes on each (same plant noise), and report each mode against rac (docs/spec.md "Beyond the
/// paper"; docs/research/robust.md).

#include <sys/stat.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <mutex>
#include <thread>

#include "cli_common.hpp"
#include "preadaptive_mrac/core/controller/mode_registry.hpp"
#include "preadaptive_mrac/core/sim/scenario_family.hpp"
#include "preadaptive_mrac/io/yaml_params.hpp"

using namespace preadaptive_mrac;

namespace {
const char* kAbout =
    "Generates `count` recurring-regime scenarios from the family seed (a first 5 s at theta = "
    "0.1 ones, then `segments` segments of 10-20 s switching between `regimes` full theta "
    "vectors with scales 0.5-10, each visited at least twice), runs rac and every mode on each "
    "with the same seeded noise (STD [rad, rad/s] on alpha and q), and prints per mode, over the "
    "repeated-switch windows, the fraction better than rac (peak |e| ratio < 1), the fraction "
    "halved (<= 0.5), the median and worst ratio; per scenario the worst IAE ratio and max|u| "
    "ratio to rac and to the oracle. With the oracle among the modes, each mode's revisits (the "
    "repeated-switch windows, back into a regime seen earlier in the scenario): their count, "
    "median and worst peak ratio to the oracle in the same window, and the fraction within 1.2x "
    "(rev:n, rev:med, rev:wst, rev<=1.2; without the oracle '-'). --out-dir writes "
    "scenario_K.yaml and runs.jsonl (one preadapt_sim --json line per run, with its revisit "
    "windows and their ratios to the oracle). --delay, --time-constant, --effectiveness and "
    "--turbulence run every mode under those plant conditions (docs/research/conditions.md); each "
    "takes "
    "one value or a range LO:HI, drawn uniformly per scenario from the family seed (the same "
    "for every mode; --effectiveness LO:HI draws one Lambda per regime, the first segment 1), "
    "reported in runs.jsonl as drawn_conditions. --mismatch M runs every scenario on a true plant "
    "whose alpha and q rows of A and entries of B are each scaled by a factor uniform in [1 - M, "
    "1 + M] (drawn per scenario from the family seed, the rest of the family unchanged), while "
    "the controller designs on the nominal plant (controller.model); runs.jsonl records each "
    "scenario's true A and B and the factors (docs/mismatch.md). --faults (plant.engine jsbsim "
    "only) gives each regime physical faults of the aircraft, drawn per regime from the family "
    "seed like --effectiveness LO:HI, the first segment nominal (docs/jsbsim.md). Every run flies "
    "the aircraft's elevator (--elevator b747: config/plant/elevator_b747.yaml over the plant "
    "file, travel 0.35 rad, rate 0.65 rad/s; --elevator ideal: the plant file alone, the paper's "
    "unlimited elevator), and with limits on the generator draws only regimes whose trim "
    "deflection is within --trim-fraction of the travel, saying how many it rejected. Beside the "
    "ratios each mode's elevator effort: peak |u| applied, time at the travel and rate limits, "
    "steady-flight total variation, fraction of each switch window at a limit. Exit code 2 on "
    "bad input.";

// "LO:HI" of a condition flag, each end within [min, max] (min excluded when min_open).
ConditionRange parseRange(const std::string& flag, const std::string& text, double min,
                          bool min_open, double max) {
  const size_t colon = text.find(':');
  ConditionRange r;
  r.lo = cli::parseDouble(flag, text.substr(0, colon));
  r.hi = cli::parseDouble(flag, text.substr(colon + 1));
  if (!(r.lo < r.hi))
    throw cli::UsageError(flag + ": a range LO:HI needs LO < HI, got '" + text + "'");
  if (!((min_open ? r.lo > min : r.lo >= min) && r.hi <= max)) {
    const std::string within = max < std::numeric_limits<double>::max()
                                   ? std::string("in ") + (min_open ? "(" : "[") +
                                         formatNumber(min) + ", " + formatNumber(max) + "]"
                                   : ">= " + formatNumber(min);
    throw cli::UsageError(flag + ": both ends must be " + within + ", got '" + text + "'");
  }
  return r;
}

// --faults "KEY=V|KEY=LO:HI,...", KEY from Scenario::kFaultKeys, each within the key's range.
FaultRanges parseFaults(const std::string& text) {
  std::string names;
  for (const auto& k : Scenario::kFaultKeys)
    names += (names.empty() ? "" : ", ") + std::string(k.name);
  FaultRanges out;
  std::vector<bool> given(Scenario::kFaultKeys.size(), false);
  for (const auto& item : cli::splitTopLevel(text)) {
    const size_t eq = item.find('=');
    size_t j = 0;
    while (j < Scenario::kFaultKeys.size() && item.substr(0, eq) != Scenario::kFaultKeys[j].name)
      ++j;
    if (eq == std::string::npos || j == Scenario::kFaultKeys.size())
      throw cli::UsageError("--faults: expected KEY=VALUE or KEY=LO:HI with KEY one of " + names +
                            ", got '" + item + "'");
    if (given[j]) throw cli::UsageError("--faults: " + item.substr(0, eq) + " given twice");
    given[j] = true;
    const auto& key = Scenario::kFaultKeys[j];
    const std::string flag = "--faults " + item.substr(0, eq), value = item.substr(eq + 1);
    ConditionRange& r = out.range[j];
    if (value.find(':') != std::string::npos) {
      r = parseRange(flag, value, key.lo, false, key.hi);
    } else {
      r.lo = r.hi = cli::parseDouble(flag, value);
      if (!(r.lo >= key.lo && r.lo <= key.hi))
        throw cli::UsageError(flag + ": " + key.what + " must be in [" + formatNumber(key.lo) +
                              ", " + formatNumber(key.hi) + "], got '" + value + "'");
    }
  }
  return out;
}

std::string fmtG(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

// The JSON key of the fraction of revisits within the tolerance names it.
static_assert(kRevisitTolerance == 1.2, "rename the JSON key within_1_2 with the tolerance");

// A mode's revisit cells of the table (count, median, worst, fraction within the tolerance):
// "-" without the oracle to compare with.
std::string revisitCells(const std::optional<RevisitSummary>& r) {
  char b[64];
  if (r)
    std::snprintf(b, sizeof b, "%5d %7.3f %7.3f %7.1f%%", r->count, r->median, r->worst,
                  100.0 * r->within);
  else
    std::snprintf(b, sizeof b, "%5s %7s %7s %8s", "-", "-", "-", "-");
  return b;
}

// runs.jsonl's "revisits" of one run: its revisit windows and, with the oracle's run of the same
// scenario, each one's peak ratio to the oracle's (null without; JSON writes inf, a lost run's
// window, as null too).
nlohmann::ordered_json revisitJson(const std::vector<bool>& repeated, const RunDigest& run,
                                   const RunDigest* oracle) {
  nlohmann::ordered_json windows = nlohmann::ordered_json::array();
  nlohmann::ordered_json ratios = oracle ? nlohmann::ordered_json::array() : nullptr;
  if (oracle) {
    for (const RevisitRatio& r : revisitRatios(repeated, *oracle, run)) {
      windows.push_back(r.window);
      ratios.push_back(r.ratio);
    }
  } else {
    for (size_t w = 1; w < repeated.size() && w < run.peak.size(); ++w)
      if (repeated[w]) windows.push_back(w);
  }
  return {{"windows", windows}, {"ratio_to_oracle", ratios}};
}

struct Job {
  int scenario = 0;
  std::string mode;
  RunConfig cfg;
  RunDigest digest;
  std::string json;
  EnvelopeExit exit;  // the run's first exit from the flight envelope (exited false: none)
};
}  // namespace

int main(int argc, char** argv) {
  return cli::runTool("preadapt_family", [&]() -> int {
    cli::RunRequest base;
    std::optional<std::uint64_t> seed;
    int count = 30;
    std::vector<std::string> modes = modeNameList();
    double noise = 0.0;
    FamilySpec spec;
    std::string out_dir;
    bool json = false;
    unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
    CLI::App app{kAbout, "preadapt_family"};
    cli::RunOptionText text;
    std::string seed_t, count_t, modes_t, noise_t, regimes_t, segments_t, ref_t, jobs_t;
    std::string delay_t, lag_t, lambda_t, gust_t, mismatch_t, faults_t;
    std::string elevator_t = "b747", trim_t;
    cli::addRunOptions(app, &base, &text, false);
    cli::addText(app, "--elevator", &elevator_t,
                 "the elevator's travel and rate: b747 (default, config/plant/elevator_b747.yaml "
                 "merged over the plant file), ideal (the plant file's own, the paper's unlimited "
                 "elevator) or a YAML path");
    cli::addText(app, "--trim-fraction", &trim_t,
                 "with elevator limits, regimes whose trim deflection exceeds this fraction of "
                 "the travel are drawn again (default 0.5; 1 = the whole travel; none = every "
                 "regime drawn is kept, as without limits)");
    cli::addText(app, "--seed", &seed_t, "the family's generator seed (required)");
    cli::addText(app, "--count", &count_t, "scenarios (default 30)");
    cli::addText(app, "--modes", &modes_t,
                 "modes to compare with rac (default " + modeNames(",") + ")");
    cli::addText(app, "--noise", &noise_t, "measurement noise std on alpha and q (default 0)");
    cli::addText(app, "--regimes", &regimes_t, "distinct regimes (default 3)");
    cli::addText(app, "--segments", &segments_t, "segments after the first (default 10)");
    cli::addText(app, "--ref-every", &ref_t, "reference steps about every S seconds (default off)");
    cli::addText(app, "--delay", &delay_t,
                 "servo transport delay [s] (plant.actuator.delay): one value for every run, or "
                 "LO:HI drawn per scenario");
    cli::addText(app, "--time-constant", &lag_t,
                 "servo lag time constant [s] (plant.actuator.time_constant): one value, or LO:HI "
                 "drawn per scenario");
    cli::addText(app, "--effectiveness", &lambda_t,
                 "elevator effectiveness Lambda in (0, 2]: one value over every scenario, or "
                 "LO:HI drawn per regime (the first segment 1)");
    cli::addText(app, "--turbulence", &gust_t,
                 "Dryden vertical gust sigma_w [m/s] (plant.turbulence, its length scale from "
                 "the YAML; the gust seed is derived from the family seed and the scenario): one "
                 "value, or LO:HI drawn per scenario");
    cli::addText(app, "--mismatch", &mismatch_t,
                 "model mismatch M in [0, 1): the true plant's alpha and q rows of A and B "
                 "scaled per entry by factors uniform in [1 - M, 1 + M], drawn per scenario; the "
                 "controller keeps the nominal model (default 0: the plant is the model)");
    cli::addText(app, "--faults", &faults_t,
                 "physical faults of the JSBSim aircraft (plant.engine jsbsim only), drawn per "
                 "regime (the first segment nominal): comma-separated KEY=VALUE or KEY=LO:HI, "
                 "KEY cg_shift (fraction of the chord, + aft, in [-0.3, 0.3]), "
                 "elevator_effectiveness or pitch_damping (multipliers in [0, 2]), e.g. "
                 "cg_shift=0:0.05,elevator_effectiveness=0.5:1,pitch_damping=0.3:1");
    cli::addText(app, "--out-dir", &out_dir, "write the scenarios and every run's JSON here");
    app.add_flag("--json", json, "also print one JSON line per mode with every ratio");
    cli::addText(app, "--jobs", &jobs_t, "threads (default: all cores)");
    if (!cli::parseCommandLine(app, argc, argv)) return 0;
    cli::finishRunOptions(text, &base);
    if (!seed_t.empty()) seed = cli::parseSeed("--seed", seed_t);
    if (!count_t.empty()) {
      const auto c = cli::parseSeed("--count", count_t);
      if (c < 1 || c > 100000) throw cli::UsageError("--count: expected 1..100000");
      count = static_cast<int>(c);
    }
    if (!modes_t.empty()) {
      modes.clear();
      for (const auto& m : cli::splitTopLevel(modes_t)) {
        if (findMode(m) == nullptr) throw cli::UsageError("--modes: unknown mode '" + m + "'");
        modes.push_back(m);
      }
    }
    if (!noise_t.empty()) {
      noise = cli::parseDouble("--noise", noise_t);
      if (noise < 0.0) throw cli::UsageError("--noise: must be >= 0");
    }
    if (!regimes_t.empty()) spec.regimes = static_cast<int>(cli::parseSeed("--regimes", regimes_t));
    if (!segments_t.empty())
      spec.segments = static_cast<int>(cli::parseSeed("--segments", segments_t));
    if (!ref_t.empty()) {
      spec.ref_every = cli::parseDouble("--ref-every", ref_t);
      if (spec.ref_every < 0.0) throw cli::UsageError("--ref-every: must be >= 0");
    }
    if (!jobs_t.empty()) {
      const auto j = cli::parseSeed("--jobs", jobs_t);
      if (j < 1 || j > 1024) throw cli::UsageError("--jobs: expected 1..1024");
      jobs = static_cast<unsigned>(j);
    }
    if (!seed) throw cli::UsageError("--seed is required (the family's generator seed)");
    if (elevator_t != "ideal")
      base.plant_presets.push_back(cli::elevatorPresetPath("--elevator", elevator_t));
    double trim_fraction = 0.5;
    const bool every_regime = trim_t == "none";
    if (!trim_t.empty() && !every_regime) {
      trim_fraction = cli::parseDouble("--trim-fraction", trim_t);
      if (!(trim_fraction > 0.0 && trim_fraction <= 1.0))
        throw cli::UsageError("--trim-fraction: expected a fraction in (0, 1], got " + trim_t);
    }
    // The conditions go in as --set overrides, so the keys' own validation names them.
    std::string conditions;
    // A range LO:HI is drawn per scenario below instead (the keys are set on each run).
    const auto condition = [&](const std::string& flag, const std::string& text,
                               const std::string& key, double max, ConditionRange* range) {
      if (text.empty()) return;
      if (text.find(':') != std::string::npos) {
        *range = parseRange(flag, text, 0.0, false, max);
        conditions += (conditions.empty() ? "" : ", ") + key + " " + text + " (per scenario)";
        return;
      }
      cli::parseDouble(flag, text);
      base.sets.push_back(key + "=" + text);
      conditions += (conditions.empty() ? "" : ", ") + key + " " + text;
    };
    ConditionRange delay_r, lag_r, gust_r, lambda_r;
    const double unbounded = std::numeric_limits<double>::max();
    condition("--delay", delay_t, "plant.actuator.delay", kMaxDelay, &delay_r);
    condition("--time-constant", lag_t, "plant.actuator.time_constant", unbounded, &lag_r);
    condition("--turbulence", gust_t, "plant.turbulence.sigma_w", unbounded, &gust_r);
    if (!gust_t.empty()) base.sets.push_back("plant.turbulence.enabled=true");
    std::optional<double> lambda;
    if (lambda_t.find(':') != std::string::npos) {
      lambda_r = parseRange("--effectiveness", lambda_t, 0.0, true, 2.0);
      conditions += (conditions.empty() ? "" : ", ") + std::string("effectiveness ") + lambda_t +
                    " (per regime, the first segment 1)";
    } else if (!lambda_t.empty()) {
      lambda = cli::parseDouble("--effectiveness", lambda_t);
      if (!(*lambda > 0.0 && *lambda <= 2.0))
        throw cli::UsageError("--effectiveness: elevator effectiveness must be in (0, 2], got " +
                              lambda_t);
      conditions += (conditions.empty() ? "" : ", ") + std::string("effectiveness ") + lambda_t;
    }
    double mismatch = 0.0;
    if (!mismatch_t.empty()) {
      mismatch = cli::parseDouble("--mismatch", mismatch_t);
      if (!(mismatch >= 0.0 && mismatch < 1.0))
        throw cli::UsageError("--mismatch: expected M in [0, 1), got " + mismatch_t);
      if (mismatch > 0.0)
        conditions += (conditions.empty() ? "" : ", ") + std::string("model mismatch ") +
                      mismatch_t + " (per scenario)";
    }
    std::optional<FaultRanges> faults;
    if (!faults_t.empty()) {
      faults = parseFaults(faults_t);
      conditions += (conditions.empty() ? "" : ", ") + std::string("faults ") + faults_t +
                    " (per regime, the first segment nominal)";
    }
    if (spec.regimes < 1 || spec.regimes > 50) throw cli::UsageError("--regimes: expected 1..50");
    if (spec.segments < 2 * spec.regimes || spec.segments > 1000)
      throw cli::UsageError("--segments: expected 2 * regimes .. 1000");
    if (std::find(modes.begin(), modes.end(), "rac") == modes.end())
      modes.insert(modes.begin(), "rac");

    // Validate the files and overrides once, through the same path as preadapt_sim.
    cli::RunRequest probe = base;
    probe.scenario = "1";
    const cli::PreparedRun prepared = cli::prepare(probe);
    spec.n = prepared.cfg.plant.n();
    if (!mismatch_t.empty() && (spec.n < 3 || prepared.cfg.plant.output_index != 1))
      throw cli::UsageError("--mismatch: needs the plant's x = [e_I, alpha, q] (output_index 1)");
    if (faults && !plantEngineRules(prepared.cfg.plant.engine).physical_faults)
      throw cli::UsageError(std::string("--faults: ") + kFaultsNeedAerodynamics +
                            " (add --set plant.engine=jsbsim); the linear model has no CG or "
                            "aerodynamics (use --effectiveness on it)");
    if (!out_dir.empty()) ::mkdir(out_dir.c_str(), 0755);
    // Feasible regimes: only with limits (off, the draws are as they always were).
    const ActuatorLimits& limits = prepared.cfg.plant.actuator;
    std::optional<TrimCheck> trim;
    if (limits.enabled && !every_regime) {
      // The controller's design model where it has one (its reference model), else the plant.
      const auto& model = prepared.cfg.controller.model;
      const auto& pl = prepared.cfg.plant;
      const Eigen::RowVectorXd K =
          prepared.cfg.design ? prepared.cfg.design->K : Eigen::RowVectorXd();
      if (K.size() == spec.n) {
        const double r_max = spec.ref_every > 0.0
                                 ? std::max(std::abs(spec.r_min), std::abs(spec.r_max))
                                 : std::abs(spec.r);
        trim = makeTrimCheck(model.A.size() ? model.A : pl.A, model.B.size() ? model.B : pl.B,
                             model.B1r.size() ? model.B1r : pl.B1r, K, r_max,
                             trim_fraction * limits.max_deflection);
      }
    }
    int rejected = 0;
    nlohmann::ordered_json elevator_json;
    elevator_json["preset"] = elevator_t;
    elevator_json["enabled"] = limits.enabled;
    elevator_json["max_deflection"] = limits.max_deflection;
    elevator_json["max_rate"] = limits.max_rate;

    std::vector<Scenario> scenarios;
    std::vector<std::vector<bool>> repeated;
    std::vector<Job> list;
    // What each scenario drew (runs.jsonl's drawn_conditions), and the span over the family.
    std::vector<nlohmann::ordered_json> drawn(static_cast<size_t>(count));
    std::map<std::string, std::pair<double, double>> span;
    const auto draw = [&](int k, const ConditionRange& r, std::uint64_t stream,
                          const std::string& key) -> std::optional<double> {
      if (!r.drawn()) return std::nullopt;
      const double v = drawCondition(r, *seed, k, stream);
      drawn[static_cast<size_t>(k)][key] = v;
      auto it = span.emplace(key, std::make_pair(v, v)).first;
      it->second = {std::min(it->second.first, v), std::max(it->second.second, v)};
      return v;
    };
    for (int k = 0; k < count; ++k) {
      scenarios.push_back(recurringScenario(spec, *seed, k, trim ? &*trim : nullptr, &rejected));
      if (lambda) scenarios.back().effectiveness = {{scenarios.back().endTime(), *lambda}};
      if (lambda_r.drawn()) {
        auto& sc = scenarios.back();
        sc.effectiveness = regimeEffectiveness(sc, lambda_r, *seed, k);
        auto& list = drawn[static_cast<size_t>(k)]["effectiveness"] =
            nlohmann::ordered_json::array();
        for (const auto& seg : sc.effectiveness) {
          list.push_back(seg.value);
          if (seg.until == sc.theta.front().until) continue;  // the first segment's 1
          auto it = span.emplace("effectiveness", std::make_pair(seg.value, seg.value)).first;
          it->second = {std::min(it->second.first, seg.value),
                        std::max(it->second.second, seg.value)};
        }
      }
      if (faults) {
        auto& sc = scenarios.back();
        sc.faults = regimeFaults(sc, *faults, *seed, k);
        auto& list = drawn[static_cast<size_t>(k)]["faults"] = nlohmann::ordered_json::array();
        for (size_t i = 0; i < sc.faults.size(); ++i) {
          auto& seg = list.emplace_back(nlohmann::ordered_json::object());
          for (const auto& key : Scenario::kFaultKeys) {
            const double v = sc.faults[i].*key.field;
            seg[key.name] = v;
            if (i == 0) continue;  // the first segment's nominal aircraft
            const std::string name = std::string("fault ") + key.name;
            auto it = span.emplace(name, std::make_pair(v, v)).first;
            it->second = {std::min(it->second.first, v), std::max(it->second.second, v)};
          }
        }
      }
      const auto delay = draw(k, delay_r, 1, "plant.actuator.delay");
      const auto lag = draw(k, lag_r, 2, "plant.actuator.time_constant");
      const auto gust = draw(k, gust_r, 3, "plant.turbulence.sigma_w");
      repeated.push_back(repeatedWindows(scenarios.back()));
      // The true plant: drawn from a stream of its own, so no other value of the family moves.
      std::optional<PlantMismatch> truth;
      if (!mismatch_t.empty()) {
        truth = mismatchedPlant(prepared.cfg.plant.A, prepared.cfg.plant.B, mismatch, *seed, k);
        if (mismatch > 0.0) {
          auto& d = drawn[static_cast<size_t>(k)];
          d["plant.A"] = nlohmann::ordered_json::array();
          for (Eigen::Index i = 0; i < truth->A.rows(); ++i) {
            auto row = nlohmann::ordered_json::array();
            for (Eigen::Index j = 0; j < truth->A.cols(); ++j) row.push_back(truth->A(i, j));
            d["plant.A"].push_back(row);
          }
          d["plant.B"] = nlohmann::ordered_json::array();
          for (Eigen::Index i = 0; i < truth->B.size(); ++i) d["plant.B"].push_back(truth->B[i]);
          d["mismatch_factors"] = truth->factors;
          for (const double f : truth->factors) {
            auto it = span.emplace("mismatch factor", std::make_pair(f, f)).first;
            it->second = {std::min(it->second.first, f), std::max(it->second.second, f)};
          }
        }
      }
      if (!out_dir.empty()) {
        std::ofstream f(out_dir + "/scenario_" + std::to_string(k) + ".yaml");
        f << scenarioToYaml(scenarios.back());
        if (!f) throw cli::UsageError("--out-dir: cannot write into '" + out_dir + "'");
      }
      for (const auto& m : modes) {
        Job job;
        job.scenario = k;
        job.mode = m;
        job.cfg = prepared.cfg;
        job.cfg.scenario = scenarios.back();
        job.cfg.controller.mode = m;
        if (noise > 0.0) {
          job.cfg.plant.noise.std = Eigen::VectorXd::Zero(spec.n);
          for (int i = 1; i < spec.n; ++i) job.cfg.plant.noise.std[i] = noise;
          job.cfg.plant.noise.seed = *seed * 1000003ULL + static_cast<std::uint64_t>(k);
        } else if (job.cfg.plant.noise.active()) {
          // Noise through --set plant.noise.std: a noise of its own per scenario as well, the
          // same for every mode (paired comparison).
          job.cfg.plant.noise.seed = *seed * 1000003ULL + static_cast<std::uint64_t>(k);
        }
        if (delay) job.cfg.plant.dynamics.delay = *delay;
        if (lag) job.cfg.plant.dynamics.time_constant = *lag;
        if (gust) job.cfg.plant.turbulence.sigma_w = *gust;
        if (truth) {
          // The controller designs on the nominal plant, the run is on the true one.
          job.cfg.controller.model.A = prepared.cfg.plant.A;
          job.cfg.controller.model.B = prepared.cfg.plant.B;
          job.cfg.controller.model.B1r = prepared.cfg.plant.B1r;
          job.cfg.plant.A = truth->A;
          job.cfg.plant.B = truth->B;
        }
        // A gust of its own per scenario, the same for every mode (paired comparison).
        if (!gust_t.empty())
          job.cfg.plant.turbulence.seed = *seed * 1000033ULL + static_cast<std::uint64_t>(k);
        list.push_back(std::move(job));
      }
    }

    std::atomic<size_t> next{0};
    std::mutex mu;
    std::string failure;
    auto worker = [&] {
      for (;;) {
        const size_t i = next.fetch_add(1);
        if (i >= list.size()) return;
        Job& job = list[i];
        try {
          Controller ctl(job.cfg.plant, job.cfg.controller);
          ClosedLoop loop(job.cfg.plant, job.cfg.scenario, &ctl);
          SimOptions opt;
          opt.dt = job.cfg.controller.sample_time;
          const auto t0 = std::chrono::steady_clock::now();
          const SimResult res = loop.run(opt);
          const double wall_s =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          for (const auto& w : res.metrics.windows) job.digest.peak.push_back(w.peak_abs_e);
          job.digest.iae = res.metrics.iae;
          job.digest.max_abs_u = res.metrics.max_abs_u;
          const EffortMetrics& ef = res.metrics.effort;
          job.digest.peak_applied = ef.peak_abs_u;
          job.digest.time_at_travel = ef.time_at_travel;
          job.digest.time_at_rate = ef.time_at_rate;
          job.digest.steady_tv = ef.steady_tv;
          for (const auto& w : res.metrics.windows)
            job.digest.limit_frac.push_back(
                w.t_end > w.t_start ? w.time_at_limit / (w.t_end - w.t_start) : 0.0);
          job.exit = res.envelope_exit;
          if (res.envelope_exit.non_finite) {
            // The run ended at its non-finite state: lost, as a run that went on in NaN was
            // (summarizeFamily: IAE not finite, the window of the blow-up the largest peak).
            job.digest.iae = INFINITY;
            job.digest.max_abs_u = INFINITY;
            for (size_t w = 0; w < res.metrics.windows.size(); ++w)
              if (res.envelope_exit.non_finite_t <= res.metrics.windows[w].t_end) {
                job.digest.peak[w] = INFINITY;
                break;
              }
          }
          if (!out_dir.empty()) {
            RunInfo info;
            info.scenario = out_dir + "/scenario_" + std::to_string(job.scenario) + ".yaml";
            info.mode = job.mode;
            info.seed = job.cfg.controller.seed;
            info.dt = opt.dt;
            info.overrides = prepared.info.overrides;  // every run's --set (and fixed conditions)
            info.wall_time_s = wall_s;
            job.json = cli::withEffort(runSummaryJson(info, ctl, res), res.metrics);
            const auto& d = drawn[static_cast<size_t>(job.scenario)];
            const bool set_noise = noise_t.empty() && job.cfg.plant.noise.active();
            if (!d.empty() || set_noise) {
              nlohmann::ordered_json line = nlohmann::ordered_json::parse(job.json);
              if (!d.empty()) line["drawn_conditions"] = d;
              if (set_noise) line["noise_seed"] = job.cfg.plant.noise.seed;  // --set noise only
              job.json = line.dump();
            }
          }
        } catch (const std::exception& e) {
          std::lock_guard<std::mutex> lk(mu);
          if (failure.empty()) failure = e.what();
        }
      }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < std::min<unsigned>(jobs, static_cast<unsigned>(list.size())); ++t)
      pool.emplace_back(worker);
    for (auto& t : pool) t.join();
    if (!failure.empty()) {
      std::cerr << "preadapt_family: error: " << failure << std::endl;
      return 1;
    }
    auto digests = [&](const std::string& m) {
      std::vector<RunDigest> d;
      for (const auto& job : list)
        if (job.mode == m) d.push_back(job.digest);
      return d;
    };
    const auto rac = digests("rac");
    const bool have_oracle = std::find(modes.begin(), modes.end(), "oracle") != modes.end();
    const auto oracle = have_oracle ? digests("oracle") : std::vector<RunDigest>{};
    if (!out_dir.empty()) {
      std::ofstream f(out_dir + "/runs.jsonl");
      for (const auto& job : list) {
        const auto k = static_cast<size_t>(job.scenario);
        nlohmann::ordered_json line = nlohmann::ordered_json::parse(job.json);
        line["revisits"] = revisitJson(repeated[k], job.digest, have_oracle ? &oracle[k] : nullptr);
        f << line.dump() << '\n';
      }
    }
    size_t rep = 0;
    for (const auto& r : repeated)
      for (size_t w = 1; w < r.size(); ++w) rep += r[w];
    // The noise as the runs have it: --noise, or else the plant's own noise.std (--set).
    std::string noise_text = fmtG(noise) + " on alpha and q";
    const MeasurementNoise& set_noise = prepared.cfg.plant.noise;
    if (noise <= 0.0 && set_noise.active()) {
      noise = set_noise.std.cwiseAbs().maxCoeff();
      noise_text = "std [";
      for (Eigen::Index i = 0; i < set_noise.std.size(); ++i)
        noise_text += (i ? ", " : "") + fmtG(set_noise.std[i]);
      noise_text += "] (plant.noise.std, a seed per scenario)";
    }
    std::printf(
        "family seed %llu: %d scenarios, %d regimes, %d segments, noise %s; %zu "
        "repeated-switch windows\n",
        static_cast<unsigned long long>(*seed), count, spec.regimes, spec.segments,
        noise_text.c_str(), rep);
    if (!conditions.empty()) std::printf("plant conditions: %s\n", conditions.c_str());
    if (trim) {
      elevator_json["trim_fraction"] = trim_fraction;
      elevator_json["rejected_regimes"] = rejected;
      std::printf(
          "elevator: %s, travel %g rad, rate %g rad/s; feasible regimes (trim within %g of the "
          "travel at |r| %g): %d drawn regimes rejected\n",
          elevator_t.c_str(), limits.max_deflection, limits.max_rate, trim_fraction, trim->r_max,
          rejected);
    } else if (limits.enabled) {
      std::printf("elevator: %s, travel %g rad, rate %g rad/s; every regime drawn kept\n",
                  elevator_t.c_str(), limits.max_deflection, limits.max_rate);
    } else {
      std::printf("elevator: %s, no travel or rate limit (the paper's idealised elevator)\n",
                  elevator_t.c_str());
    }
    for (const auto& kv : span)
      std::printf("drawn: %s in [%.6g, %.6g]\n", kv.first.c_str(), kv.second.first,
                  kv.second.second);
    // Effort beside the ratios, after " || ": applied elevator's peak |u| (median, worst) [rad],
    // time at the travel and rate limits (median) [s], steady-flight total variation (median)
    // [rad], fraction of a switch window at a limit (median, worst).
    // The revisits, after u/oracle: count, median and worst peak ratio to the oracle, the
    // fraction within kRevisitTolerance.
    const std::string within_head = "rev<=" + fmtG(kRevisitTolerance);
    std::printf(
        "%-15s %7s %7s %7s %7s | %8s %7s | %8s %5s | %8s %8s | %5s %7s %7s %8s || %6s %6s %7s "
        "%7s %7s %6s %6s\n",
        "mode", "better", "halved", "median", "worst", "all:med", "worst", "IAE:wst", ">5%",
        "u/rac", "u/oracle", "rev:n", "rev:med", "rev:wst", within_head.c_str(), "|u|med", "|u|wst",
        "trav[s]", "rate[s]", "TV:med", "lim:md", "lim:wst");
    for (const auto& m : modes) {
      const auto runs = digests(m);
      const FamilySummary s = summarizeFamily(repeated, rac, runs, have_oracle ? &oracle : nullptr);
      const EffortSummary ef = summarizeEffort(runs);
      std::optional<RevisitSummary> rev;
      if (have_oracle) rev = summarizeRevisits(repeated, oracle, runs);
      std::printf(
          "%-15s %6.1f%% %6.1f%% %7.3f %7.3f | %8.3f %7.3f | %8.3f %5d | %8.3f %8.3f | %s || "
          "%6.3f %6.3f %7.2f %7.2f %7.4f %5.1f%% %5.1f%%\n",
          m.c_str(), 100.0 * s.frac_better, 100.0 * s.frac_halved, s.median_ratio, s.worst_ratio,
          s.all_median_ratio, s.all_worst_ratio, s.worst_iae_ratio, s.iae_over, s.worst_u_rac,
          s.worst_u_oracle, revisitCells(rev).c_str(), ef.median_peak_u, ef.worst_peak_u,
          ef.median_travel, ef.median_rate, ef.median_tv, 100.0 * ef.median_window_limit,
          100.0 * ef.worst_window_limit);
      if (s.lost_runs > 0) std::printf("%-15s %d runs lost (diverged)\n", m.c_str(), s.lost_runs);
      nlohmann::ordered_json exits = nlohmann::ordered_json::array();
      for (const auto& job : list) {
        if (job.mode != m || !job.exit.exited) continue;
        std::printf("%-15s scenario %d %s\n", m.c_str(), job.scenario,
                    cli::envelopeNote(job.exit).c_str());
        exits.push_back({{"scenario", job.scenario},
                         {"t", job.exit.t},
                         {"bound", job.exit.bound},
                         {"non_finite", job.exit.non_finite}});
      }
      if (json) {
        nlohmann::ordered_json o;
        o["mode"] = m;
        o["seed"] = *seed;
        o["count"] = count;
        o["noise"] = noise;
        if (!conditions.empty()) o["conditions"] = conditions;
        for (const auto& kv : span) o["drawn"][kv.first] = {kv.second.first, kv.second.second};
        o["windows"] = s.windows;
        o["frac_better"] = s.frac_better;
        o["frac_halved"] = s.frac_halved;
        o["median_ratio"] = s.median_ratio;
        o["worst_ratio"] = s.worst_ratio;
        o["all_median_ratio"] = s.all_median_ratio;
        o["all_worst_ratio"] = s.all_worst_ratio;
        o["worst_iae_ratio"] = s.worst_iae_ratio;
        o["iae_over_5pct"] = s.iae_over;
        o["worst_u_rac"] = s.worst_u_rac;
        o["worst_u_oracle"] = s.worst_u_oracle;
        o["ratios"] = s.ratios;
        if (rev)
          o["revisits"] = {{"count", rev->count},
                           {"median", rev->median},
                           {"worst", rev->worst},
                           {"within_1_2", rev->within}};
        else
          o["revisits"] = nullptr;
        if (s.lost_runs > 0) o["lost_runs"] = s.lost_runs;
        if (!exits.empty()) o["envelope_exits"] = exits;  // absent: every run stayed inside
        o["effort"] = {{"median_peak_abs_u", ef.median_peak_u},
                       {"worst_peak_abs_u", ef.worst_peak_u},
                       {"median_time_at_travel_limit", ef.median_travel},
                       {"worst_time_at_travel_limit", ef.worst_travel},
                       {"median_time_at_rate_limit", ef.median_rate},
                       {"worst_time_at_rate_limit", ef.worst_rate},
                       {"median_steady_tv", ef.median_tv},
                       {"worst_steady_tv", ef.worst_tv},
                       {"median_window_frac_at_limit", ef.median_window_limit},
                       {"worst_window_frac_at_limit", ef.worst_window_limit}};
        o["elevator"] = elevator_json;
        std::printf("%s\n", o.dump().c_str());
      }
    }
    return 0;
  });
}
