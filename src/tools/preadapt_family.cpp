/// \file preadapt_family.cpp
/// \brief Families of random recurring-regime scenarios: write them, run rac and the chosen
/// modes on each (same plant noise), and report each mode against rac (docs/spec.md "Beyond the
/// paper"; docs/research/robust.md). This file parses the command line and runs the steps of
/// family_tool.hpp in turn.

#include <algorithm>
#include <iostream>
#include <limits>
#include <thread>

#include "aircraft_elevator.hpp"
#include "family_tool.hpp"
#include "preadaptive_mrac/core/controller/mode_registry.hpp"

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
    "windows and their ratios to the oracle). With sensor noise, a switch window where rac's "
    "peak |e| is within twice the noise's largest excursion is quiet (the switch hidden in the "
    "noise) and judged by no ratio; the summary counts them (--quiet-factor). --delay, "
    "--time-constant, --effectiveness and "
    "--turbulence run every mode under those plant conditions (docs/research/conditions.md); each "
    "takes "
    "one value or a range LO:HI, drawn uniformly per scenario from the family seed (the same "
    "for every mode; --effectiveness LO:HI draws one Lambda per regime, the first segment 1), "
    "reported in runs.jsonl as drawn_conditions. --mismatch M runs every scenario on a true plant "
    "whose alpha and q rows of A and entries of B are each scaled by a factor uniform in [1 - M, "
    "1 + M] (drawn per scenario from the family seed, the rest of the family unchanged), while "
    "the controller designs on the nominal plant (controller.model); runs.jsonl records each "
    "scenario's true A and B and the factors (docs/research/mismatch.md). --faults (plant.engine "
    "jsbsim "
    "only) gives each regime physical faults of the aircraft, drawn per regime from the family "
    "seed like --effectiveness LO:HI, the first segment nominal (docs/jsbsim.md). Every run flies "
    "the aircraft's elevator (by default an ordinary JSBSim aircraft's own, else --elevator "
    "b747: config/plant/elevator_b747.yaml over the plant file, travel 0.35 rad, rate 0.65 "
    "rad/s; --elevator ideal: the plant file alone, the paper's unlimited elevator), and with "
    "limits on the generator draws only regimes whose trim "
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

// The flags as text, checked by parseOptions().
struct OptionText {
  cli::RunOptionText run;
  std::string seed, count, modes, noise, regimes, segments, ref, jobs, scales, reference;
  std::string delay, lag, lambda, gust, mismatch, faults;
  std::string elevator, trim, quiet;
};

void addOptions(CLI::App& app, family::Options* opt, OptionText* t) {
  cli::addRunOptions(app, &opt->base, &t->run, false);
  cli::addText(app, "--elevator", &t->elevator,
               "the elevator's travel and rate: b747 (config/plant/elevator_b747.yaml merged "
               "over the plant file), ideal (the plant file's own, the paper's unlimited "
               "elevator) or a YAML path; default: an ordinary JSBSim aircraft's own (its "
               "flight control system's travel and rate), else b747");
  cli::addText(app, "--trim-fraction", &t->trim,
               "with elevator limits, regimes whose trim deflection exceeds this fraction of "
               "the travel are drawn again (default 0.5; 1 = the whole travel; none = every "
               "regime drawn is kept, as without limits)");
  cli::addText(app, "--quiet-factor", &t->quiet,
               "with sensor noise, a switch window where rac's peak |e| is at most this many "
               "times the noise's largest excursion over the window is quiet and judged by no "
               "ratio (default 2: what the switch adds to rac's peak is no larger than the "
               "noise; 0: every window judged)");
  cli::addText(app, "--seed", &t->seed, "the family's generator seed (required)");
  cli::addText(app, "--count", &t->count, "scenarios (default 30)");
  cli::addText(app, "--modes", &t->modes,
               "modes to compare with rac (default " + modeNames(",") + ")");
  cli::addText(app, "--noise", &t->noise, "measurement noise std on alpha and q (default 0)");
  cli::addText(app, "--regimes", &t->regimes, "distinct regimes (default 3)");
  cli::addText(app, "--segments", &t->segments, "segments after the first (default 10)");
  cli::addText(app, "--ref-every", &t->ref, "reference steps about every S seconds (default off)");
  cli::addText(app, "--scales", &t->scales,
               "regime scales s, log-uniform in |s| over LO:HI, both ends of one sign (default "
               "0.5:10; negative scales make an aircraft less stable in pitch)");
  cli::addText(app, "--reference", &t->reference,
               "with --ref-every: the alpha command [rad] at each step, uniform in LO:HI, the "
               "first (LO + HI) / 2 (default 0.05:0.15, the first 0.1)");
  cli::addText(app, "--delay", &t->delay,
               "servo transport delay [s] (plant.actuator.delay): one value for every run, or "
               "LO:HI drawn per scenario");
  cli::addText(app, "--time-constant", &t->lag,
               "servo lag time constant [s] (plant.actuator.time_constant): one value, or LO:HI "
               "drawn per scenario");
  cli::addText(app, "--effectiveness", &t->lambda,
               "elevator effectiveness Lambda in (0, 2]: one value over every scenario, or "
               "LO:HI drawn per regime (the first segment 1)");
  cli::addText(app, "--turbulence", &t->gust,
               "Dryden vertical gust sigma_w [m/s] (plant.turbulence, its length scale from "
               "the YAML; the gust seed is derived from the family seed and the scenario): one "
               "value, or LO:HI drawn per scenario");
  cli::addText(app, "--mismatch", &t->mismatch,
               "model mismatch M in [0, 1): the true plant's alpha and q rows of A and B "
               "scaled per entry by factors uniform in [1 - M, 1 + M], drawn per scenario; the "
               "controller keeps the nominal model (default 0: the plant is the model)");
  cli::addText(app, "--faults", &t->faults,
               "physical faults of the JSBSim aircraft (plant.engine jsbsim only), drawn per "
               "regime (the first segment nominal): comma-separated KEY=VALUE or KEY=LO:HI, "
               "KEY cg_shift (fraction of the chord, + aft, in [-0.3, 0.3]), "
               "elevator_effectiveness or pitch_damping (multipliers in [0, 2]), e.g. "
               "cg_shift=0:0.05,elevator_effectiveness=0.5:1,pitch_damping=0.3:1");
  cli::addText(app, "--out-dir", &opt->out_dir,
               "write the scenarios and every run's JSON here (a folder that holds an earlier "
               "family's runs.jsonl or scenario files is refused unless --force)");
  app.add_flag("--force", opt->force, "with --out-dir: replace an earlier family's files there");
  app.add_flag("--json", opt->json, "also print one JSON line per mode with every ratio");
  cli::addText(app, "--jobs", &t->jobs, "threads (default: all cores)");
}

// The family's size, the modes, the noise and the threads.
void parseShape(const OptionText& t, family::Options* opt) {
  if (!t.seed.empty()) opt->seed = cli::parseSeed("--seed", t.seed);
  if (!t.count.empty()) opt->count = cli::parseCount("--count", t.count, 100000);
  if (!t.modes.empty()) {
    opt->modes.clear();
    for (const auto& m : cli::splitTopLevel(t.modes)) {
      if (findMode(m) == nullptr) throw cli::UsageError("--modes: unknown mode '" + m + "'");
      opt->modes.push_back(m);
    }
  }
  if (!t.noise.empty()) {
    opt->noise = cli::parseDouble("--noise", t.noise);
    if (opt->noise < 0.0) throw cli::UsageError("--noise: must be >= 0");
    opt->noise_given = true;
  }
  if (!t.regimes.empty()) opt->spec.regimes = cli::parseCount("--regimes", t.regimes, 50);
  if (!t.segments.empty()) opt->spec.segments = cli::parseCount("--segments", t.segments, 1000);
  if (!t.ref.empty()) {
    opt->spec.ref_every = cli::parseDouble("--ref-every", t.ref);
    if (opt->spec.ref_every < 0.0) throw cli::UsageError("--ref-every: must be >= 0");
  }
  if (!t.scales.empty()) {
    const ConditionRange r = parseRange("--scales", t.scales, -std::numeric_limits<double>::max(),
                                        false, std::numeric_limits<double>::max());
    if (!(r.lo > 0.0 || r.hi < 0.0))
      throw cli::UsageError("--scales: both ends must be of one sign and not 0, got '" + t.scales +
                            "'");
    opt->spec.min_scale = r.lo;
    opt->spec.max_scale = r.hi;
  }
  if (!t.reference.empty()) {
    if (opt->spec.ref_every <= 0.0)
      throw cli::UsageError("--reference: needs --ref-every (the command steps)");
    const ConditionRange r =
        parseRange("--reference", t.reference, -std::numeric_limits<double>::max(), false,
                   std::numeric_limits<double>::max());
    opt->spec.r_min = r.lo;
    opt->spec.r_max = r.hi;
    opt->spec.r = 0.5 * (r.lo + r.hi);
  }
  if (!t.jobs.empty()) opt->jobs = static_cast<unsigned>(cli::parseCount("--jobs", t.jobs, 1024));
  if (t.seed.empty()) throw cli::UsageError("--seed is required (the family's generator seed)");
}

// The plant conditions: one value goes in as a --set override (so the key's own validation
// names it), a range LO:HI is drawn per scenario (per regime: Lambda, the faults) instead.
void parseConditions(const OptionText& t, family::Options* opt) {
  std::string& conditions = opt->conditions;
  const auto add = [&](const std::string& what) {
    conditions += (conditions.empty() ? "" : ", ") + what;
  };
  const auto condition = [&](const std::string& flag, const std::string& text,
                             const std::string& key, double max, ConditionRange* range) {
    if (text.empty()) return;
    if (text.find(':') != std::string::npos) {
      *range = parseRange(flag, text, 0.0, false, max);
      add(key + " " + text + " (per scenario)");
      return;
    }
    cli::parseDouble(flag, text);
    opt->base.sets.push_back(key + "=" + text);
    add(key + " " + text);
  };
  const double unbounded = std::numeric_limits<double>::max();
  condition("--delay", t.delay, "plant.actuator.delay", kMaxDelay, &opt->delay);
  condition("--time-constant", t.lag, "plant.actuator.time_constant", unbounded, &opt->lag);
  condition("--turbulence", t.gust, "plant.turbulence.sigma_w", unbounded, &opt->gust);
  opt->turbulence = !t.gust.empty();
  if (opt->turbulence) opt->base.sets.push_back("plant.turbulence.enabled=true");
  if (t.lambda.find(':') != std::string::npos) {
    opt->lambda_range = parseRange("--effectiveness", t.lambda, 0.0, true, 2.0);
    add("effectiveness " + t.lambda + " (per regime, the first segment 1)");
  } else if (!t.lambda.empty()) {
    opt->lambda = cli::parseDouble("--effectiveness", t.lambda);
    if (!(*opt->lambda > 0.0 && *opt->lambda <= 2.0))
      throw cli::UsageError("--effectiveness: elevator effectiveness must be in (0, 2], got " +
                            t.lambda);
    add("effectiveness " + t.lambda);
  }
  if (!t.mismatch.empty()) {
    opt->mismatch = cli::parseDouble("--mismatch", t.mismatch);
    if (!(*opt->mismatch >= 0.0 && *opt->mismatch < 1.0))
      throw cli::UsageError("--mismatch: expected M in [0, 1), got " + t.mismatch);
    if (*opt->mismatch > 0.0) add("model mismatch " + t.mismatch + " (per scenario)");
  }
  if (!t.faults.empty()) {
    opt->faults = parseFaults(t.faults);
    add("faults " + t.faults + " (per regime, the first segment nominal)");
  }
}
}  // namespace

namespace preadaptive_mrac {
namespace family {

bool parseOptions(int argc, char** argv, Options* opt) {
  opt->modes = modeNameList();
  opt->jobs = std::max(1u, std::thread::hardware_concurrency());
  CLI::App app{kAbout, "preadapt_family"};
  OptionText t;
  addOptions(app, opt, &t);
  if (!cli::parseCommandLine(app, argc, argv)) return false;
  cli::finishRunOptions(t.run, &opt->base);
  parseShape(t, opt);
  opt->elevator = t.elevator;
  if (t.elevator.empty())
    opt->elevator = cli::addAircraftElevator(cli::prepare(opt->base).cfg.plant, &opt->base,
                                             "preadapt_family", true);
  else if (t.elevator != "ideal")
    opt->base.plant_presets.push_back(cli::elevatorPresetPath("--elevator", t.elevator));
  opt->every_regime = t.trim == "none";
  if (!t.trim.empty() && !opt->every_regime) {
    opt->trim_fraction = cli::parseDouble("--trim-fraction", t.trim);
    if (!(opt->trim_fraction > 0.0 && opt->trim_fraction <= 1.0))
      throw cli::UsageError("--trim-fraction: expected a fraction in (0, 1], got " + t.trim);
  }
  if (!t.quiet.empty()) {
    opt->quiet_factor = cli::parseDouble("--quiet-factor", t.quiet);
    if (!(opt->quiet_factor >= 0.0 && opt->quiet_factor <= 100.0))
      throw cli::UsageError("--quiet-factor: expected a factor in [0, 100], got " + t.quiet);
  }
  parseConditions(t, opt);
  if (opt->spec.segments < 2 * opt->spec.regimes)
    throw cli::UsageError("--segments: expected 2 * regimes .. 1000");
  if (std::find(opt->modes.begin(), opt->modes.end(), "rac") == opt->modes.end())
    opt->modes.insert(opt->modes.begin(), "rac");
  return true;
}

}  // namespace family
}  // namespace preadaptive_mrac

int main(int argc, char** argv) {
  return cli::runTool("preadapt_family", [&]() -> int {
    family::Options opt;
    if (!family::parseOptions(argc, argv, &opt)) return 0;
    family::Family fam = family::drawFamily(opt);
    const std::string failure = family::runFamily(opt, &fam);
    if (!failure.empty()) {
      std::cerr << "preadapt_family: error: " << failure << std::endl;
      return 1;
    }
    family::markQuietWindows(opt, &fam);
    family::reportFamily(opt, fam);
    return 0;
  });
}
