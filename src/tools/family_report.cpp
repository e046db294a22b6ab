/// \file family_report.cpp
/// \brief preadapt_family's report: runs.jsonl with each run's revisits, the family's summary
/// lines, then per mode its table row against rac (and the oracle) and, with --json, its line.

#include <cstdio>
#include <fstream>

#include "family_tool.hpp"

namespace preadaptive_mrac {
namespace family {
namespace {

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
// window, as null too), and whether each is quiet (the quiet ones are listed too).
nlohmann::ordered_json revisitJson(const std::vector<bool>& repeated,
                                   const std::vector<bool>& quiet, const RunDigest& run,
                                   const RunDigest* oracle) {
  nlohmann::ordered_json windows = nlohmann::ordered_json::array();
  nlohmann::ordered_json ratios = oracle ? nlohmann::ordered_json::array() : nullptr;
  nlohmann::ordered_json quiet_flags = nlohmann::ordered_json::array();
  if (oracle) {
    for (const RevisitRatio& r : revisitRatios(repeated, *oracle, run)) {
      windows.push_back(r.window);
      ratios.push_back(r.ratio);
    }
  } else {
    for (size_t w = 1; w < repeated.size() && w < run.peak.size(); ++w)
      if (repeated[w]) windows.push_back(w);
  }
  for (const auto& w : windows) {
    const auto i = w.get<size_t>();
    quiet_flags.push_back(i < quiet.size() && quiet[i]);
  }
  return {{"windows", windows}, {"ratio_to_oracle", ratios}, {"quiet", quiet_flags}};
}

// One mode's runs, scenario by scenario.
std::vector<RunDigest> digests(const std::vector<Job>& jobs, const std::string& mode) {
  std::vector<RunDigest> d;
  for (const auto& job : jobs)
    if (job.mode == mode) d.push_back(job.digest);
  return d;
}

void writeRuns(const std::string& path, const Family& fam, const std::vector<RunDigest>* oracle) {
  std::ofstream f(path);
  for (const auto& job : fam.jobs) {
    const auto k = static_cast<size_t>(job.scenario);
    nlohmann::ordered_json line = nlohmann::ordered_json::parse(job.json);
    line["revisits"] =
        revisitJson(fam.repeated[k], fam.quiet[k], job.digest, oracle ? &(*oracle)[k] : nullptr);
    f << line.dump() << '\n';
  }
}

// The elevator every run flew, and with limits the regimes rejected as untrimmable.
nlohmann::ordered_json elevatorJson(const Options& opt, const Family& fam) {
  const ActuatorLimits& limits = fam.prepared.cfg.plant.actuator;
  nlohmann::ordered_json j;
  j["preset"] = opt.elevator;
  j["enabled"] = limits.enabled;
  j["max_deflection"] = limits.max_deflection;
  j["max_rate"] = limits.max_rate;
  if (fam.trim) {
    j["trim_fraction"] = opt.trim_fraction;
    j["rejected_regimes"] = fam.rejected;
  }
  return j;
}

// The lines above the table: the family, its conditions, its elevator and the draws' spans.
// Returns the noise as the JSON lines give it: --noise, or else the largest of the plant's own
// noise.std (--set).
double printSummary(const Options& opt, const Family& fam) {
  size_t rep = 0;
  for (const auto& r : fam.repeated)
    for (size_t w = 1; w < r.size(); ++w) rep += r[w];
  double noise = opt.noise;
  std::string noise_text = fmtG(noise) + " on alpha and q";
  const MeasurementNoise& set_noise = fam.prepared.cfg.plant.noise;
  if (noise <= 0.0 && set_noise.active()) {
    noise = set_noise.std.cwiseAbs().maxCoeff();
    noise_text = "std [";
    for (Eigen::Index i = 0; i < set_noise.std.size(); ++i)
      noise_text += (i ? ", " : "") + fmtG(set_noise.std[i]);
    noise_text += "] (plant.noise.std, a seed per scenario)";
  }
  size_t quiet = 0;
  for (size_t k = 0; k < fam.quiet.size() && k < fam.repeated.size(); ++k)
    for (size_t w = 1; w < fam.quiet[k].size() && w < fam.repeated[k].size(); ++w)
      quiet += fam.quiet[k][w] && fam.repeated[k][w];
  std::printf(
      "family seed %llu: %d scenarios, %d regimes, %d segments, noise %s; %zu "
      "repeated-switch windows\n",
      static_cast<unsigned long long>(opt.seed), opt.count, opt.spec.regimes, opt.spec.segments,
      noise_text.c_str(), rep);
  if (quiet > 0)
    std::printf(
        "quiet windows: %zu of the %zu, not judged (rac's peak |e| within %g x the sensor "
        "noise's largest excursion: the switch is hidden in the noise; --quiet-factor)\n",
        quiet, rep, opt.quiet_factor);
  if (!opt.conditions.empty()) std::printf("plant conditions: %s\n", opt.conditions.c_str());
  const ActuatorLimits& limits = fam.prepared.cfg.plant.actuator;
  if (fam.trim) {
    std::printf(
        "elevator: %s, travel %g rad, rate %g rad/s; feasible regimes (trim within %g of the "
        "travel at |r| %g): %d drawn regimes rejected\n",
        opt.elevator.c_str(), limits.max_deflection, limits.max_rate, opt.trim_fraction,
        fam.trim->r_max, fam.rejected);
  } else if (limits.enabled) {
    std::printf("elevator: %s, travel %g rad, rate %g rad/s; every regime drawn kept\n",
                opt.elevator.c_str(), limits.max_deflection, limits.max_rate);
  } else {
    std::printf("elevator: %s, no travel or rate limit (the paper's idealised elevator)\n",
                opt.elevator.c_str());
  }
  for (const auto& kv : fam.span)
    std::printf("drawn: %s in [%.6g, %.6g]\n", kv.first.c_str(), kv.second.first, kv.second.second);
  return noise;
}

// Effort beside the ratios, after " || ": applied elevator's peak |u| (median, worst) [rad],
// time at the travel and rate limits (median) [s], steady-flight total variation (median)
// [rad], fraction of a switch window at a limit (median, worst).
// The revisits, after u/oracle: count, median and worst peak ratio to the oracle, the
// fraction within kRevisitTolerance.
void printTableHead() {
  const std::string within_head = "rev<=" + fmtG(kRevisitTolerance);
  std::printf(
      "%-15s %7s %7s %7s %7s | %8s %7s | %8s %5s | %8s %8s | %5s %7s %7s %8s || %6s %6s %7s "
      "%7s %7s %6s %6s\n",
      "mode", "better", "halved", "median", "worst", "all:med", "worst", "IAE:wst", ">5%", "u/rac",
      "u/oracle", "rev:n", "rev:med", "rev:wst", within_head.c_str(), "|u|med", "|u|wst", "trav[s]",
      "rate[s]", "TV:med", "lim:md", "lim:wst");
}

// What the report says of one mode.
struct ModeReport {
  FamilySummary s;
  EffortSummary effort;
  std::optional<RevisitSummary> revisits;  ///< none without the oracle
  nlohmann::ordered_json exits;            ///< its runs that left the flight envelope
};

// The mode's table row, its lost runs and its runs that left the envelope (filling r->exits).
void printModeRows(const std::string& m, const std::vector<Job>& jobs, ModeReport* r) {
  const FamilySummary& s = r->s;
  const EffortSummary& ef = r->effort;
  std::printf(
      "%-15s %6.1f%% %6.1f%% %7.3f %7.3f | %8.3f %7.3f | %8.3f %5d | %8.3f %8.3f | %s || "
      "%6.3f %6.3f %7.2f %7.2f %7.4f %5.1f%% %5.1f%%\n",
      m.c_str(), 100.0 * s.frac_better, 100.0 * s.frac_halved, s.median_ratio, s.worst_ratio,
      s.all_median_ratio, s.all_worst_ratio, s.worst_iae_ratio, s.iae_over, s.worst_u_rac,
      s.worst_u_oracle, revisitCells(r->revisits).c_str(), ef.median_peak_u, ef.worst_peak_u,
      ef.median_travel, ef.median_rate, ef.median_tv, 100.0 * ef.median_window_limit,
      100.0 * ef.worst_window_limit);
  if (s.lost_runs > 0) std::printf("%-15s %d runs lost (diverged)\n", m.c_str(), s.lost_runs);
  r->exits = nlohmann::ordered_json::array();
  for (const auto& job : jobs) {
    if (job.mode != m || !job.exit.exited) continue;
    std::printf("%-15s scenario %d %s\n", m.c_str(), job.scenario,
                cli::envelopeNote(job.exit).c_str());
    r->exits.push_back({{"scenario", job.scenario},
                        {"t", job.exit.t},
                        {"bound", job.exit.bound},
                        {"non_finite", job.exit.non_finite}});
  }
}

nlohmann::ordered_json effortJson(const EffortSummary& ef) {
  return {{"median_peak_abs_u", ef.median_peak_u},
          {"worst_peak_abs_u", ef.worst_peak_u},
          {"median_time_at_travel_limit", ef.median_travel},
          {"worst_time_at_travel_limit", ef.worst_travel},
          {"median_time_at_rate_limit", ef.median_rate},
          {"worst_time_at_rate_limit", ef.worst_rate},
          {"median_steady_tv", ef.median_tv},
          {"worst_steady_tv", ef.worst_tv},
          {"median_window_frac_at_limit", ef.median_window_limit},
          {"worst_window_frac_at_limit", ef.worst_window_limit}};
}

// The mode's --json line: the family, every ratio, the revisits, the effort and the elevator.
nlohmann::ordered_json modeJson(const Options& opt, const Family& fam, double noise,
                                const std::string& m, const ModeReport& r) {
  const FamilySummary& s = r.s;
  nlohmann::ordered_json o;
  o["mode"] = m;
  o["seed"] = opt.seed;
  o["count"] = opt.count;
  o["noise"] = noise;
  if (!opt.conditions.empty()) o["conditions"] = opt.conditions;
  for (const auto& kv : fam.span) o["drawn"][kv.first] = {kv.second.first, kv.second.second};
  o["windows"] = s.windows;
  o["quiet_windows"] = s.quiet;
  o["quiet_factor"] = opt.quiet_factor;
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
  if (r.revisits)
    o["revisits"] = {{"count", r.revisits->count},
                     {"median", r.revisits->median},
                     {"worst", r.revisits->worst},
                     {"within_1_2", r.revisits->within}};
  else
    o["revisits"] = nullptr;
  if (s.lost_runs > 0) o["lost_runs"] = s.lost_runs;
  if (!r.exits.empty()) o["envelope_exits"] = r.exits;  // absent: every run stayed inside
  o["effort"] = effortJson(r.effort);
  o["elevator"] = elevatorJson(opt, fam);
  return o;
}
}  // namespace

void markQuietWindows(const Options& opt, Family* fam) {
  fam->quiet.assign(fam->repeated.size(), {});
  for (const auto& job : fam->jobs) {
    if (job.mode != "rac") continue;
    const MeasurementNoise& noise = job.cfg.plant.noise;
    const auto out = static_cast<Eigen::Index>(job.cfg.plant.output_index);
    const double sigma = noise.active() && out < noise.std.size() ? std::abs(noise.std[out]) : 0.0;
    fam->quiet[static_cast<size_t>(job.scenario)] = quietWindows(
        job.cfg.scenario, job.cfg.controller.sample_time, sigma, job.digest, opt.quiet_factor);
  }
}

void reportFamily(const Options& opt, const Family& fam) {
  const auto rac = digests(fam.jobs, "rac");
  const bool have_oracle =
      std::find(opt.modes.begin(), opt.modes.end(), "oracle") != opt.modes.end();
  const auto oracle = have_oracle ? digests(fam.jobs, "oracle") : std::vector<RunDigest>{};
  if (!opt.out_dir.empty())
    writeRuns(opt.out_dir + "/runs.jsonl", fam, have_oracle ? &oracle : nullptr);
  const double noise = printSummary(opt, fam);
  printTableHead();
  for (const auto& m : opt.modes) {
    const auto runs = digests(fam.jobs, m);
    ModeReport r;
    r.s = summarizeFamily(fam.repeated, rac, runs, have_oracle ? &oracle : nullptr, &fam.quiet);
    r.effort = summarizeEffort(runs);
    if (have_oracle) r.revisits = summarizeRevisits(fam.repeated, oracle, runs, &fam.quiet);
    printModeRows(m, fam.jobs, &r);
    if (opt.json) std::printf("%s\n", modeJson(opt, fam, noise, m, r).dump().c_str());
  }
}

}  // namespace family
}  // namespace preadaptive_mrac
