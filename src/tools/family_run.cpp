/// \file family_run.cpp
/// \brief preadapt_family's run: every job's closed loop on a pool of threads, each reduced to
/// what the report needs (RunDigest) and, with --out-dir, its runs.jsonl line.

#include <atomic>
#include <chrono>
#include <cmath>
#include <iostream>
#include <mutex>
#include <thread>

#include "family_tool.hpp"

namespace preadaptive_mrac {
namespace family {
namespace {

// What the report needs of a run: peaks per window, IAE, max |u| and the elevator effort.
RunDigest digestOf(const SimResult& res) {
  RunDigest digest;
  for (const auto& w : res.metrics.windows) digest.peak.push_back(w.peak_abs_e);
  digest.iae = res.metrics.iae;
  digest.max_abs_u = res.metrics.max_abs_u;
  const EffortMetrics& ef = res.metrics.effort;
  digest.peak_applied = ef.peak_abs_u;
  digest.time_at_travel = ef.time_at_travel;
  digest.time_at_rate = ef.time_at_rate;
  digest.steady_tv = ef.steady_tv;
  for (const auto& w : res.metrics.windows)
    digest.limit_frac.push_back(w.t_end > w.t_start ? w.time_at_limit / (w.t_end - w.t_start)
                                                    : 0.0);
  if (res.envelope_exit.non_finite) {
    // The run ended at its non-finite state: lost, as a run that went on in NaN was
    // (summarizeFamily: IAE not finite, the window of the blow-up the largest peak).
    digest.iae = INFINITY;
    digest.max_abs_u = INFINITY;
    for (size_t w = 0; w < res.metrics.windows.size(); ++w)
      if (res.envelope_exit.non_finite_t <= res.metrics.windows[w].t_end) {
        digest.peak[w] = INFINITY;
        break;
      }
  }
  return digest;
}

// The run's runs.jsonl line, without its revisits (the report adds them, with every run done).
std::string runJson(const Options& opt, const Family& fam, const Job& job, const Controller& ctl,
                    const SimResult& res, double dt, double wall_s) {
  RunInfo info;
  info.scenario = opt.out_dir + "/scenario_" + std::to_string(job.scenario) + ".yaml";
  info.mode = job.mode;
  info.seed = job.cfg.controller.seed;
  info.dt = dt;
  info.overrides = fam.prepared.info.overrides;  // every run's --set (and fixed conditions)
  info.wall_time_s = wall_s;
  std::string json = cli::withEffort(runSummaryJson(info, ctl, res), res.metrics);
  const auto& d = fam.drawn[static_cast<size_t>(job.scenario)];
  const bool set_noise = !opt.noise_given && job.cfg.plant.noise.active();
  if (d.empty() && !set_noise) return json;
  nlohmann::ordered_json line = nlohmann::ordered_json::parse(json);
  if (!d.empty()) line["drawn_conditions"] = d;
  if (set_noise) line["noise_seed"] = job.cfg.plant.noise.seed;  // --set noise only
  return line.dump();
}

void runJob(const Options& opt, const Family& fam, Job* job) {
  Controller ctl(designModelOf(job->cfg.plant, job->cfg.controller), job->cfg.controller);
  ClosedLoop loop(job->cfg.plant, job->cfg.scenario, &ctl);
  SimOptions sim;
  sim.dt = job->cfg.controller.sample_time;
  const auto t0 = std::chrono::steady_clock::now();
  const SimResult res = loop.run(sim);
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  job->digest = digestOf(res);
  job->exit = res.envelope_exit;
  if (!opt.out_dir.empty()) job->json = runJson(opt, fam, *job, ctl, res, sim.dt, wall_s);
}
}  // namespace

std::string runFamily(const Options& opt, Family* fam) {
  std::vector<Job>& list = fam->jobs;
  std::atomic<size_t> next{0};
  std::mutex mu;
  std::string failure;
  auto worker = [&] {
    for (;;) {
      const size_t i = next.fetch_add(1);
      if (i >= list.size()) return;
      // A run that fails is run once more: a JSBSim process starved past plant.jsbsim.timeout
      // on a loaded machine must not cost the whole family. Runs are deterministic, so the
      // second run's result is the one the first would have given; a cause that stays (a
      // missing file) fails again and is reported.
      for (int attempt = 1;; ++attempt) {
        try {
          runJob(opt, *fam, &list[i]);
          break;
        } catch (const std::exception& e) {
          const std::string what = "scenario " + std::to_string(list[i].scenario) + ", mode " +
                                   list[i].mode + ": " + e.what();
          std::lock_guard<std::mutex> lk(mu);
          if (attempt < 2) {
            std::cerr << "preadapt_family: " << what << "; running it once more" << std::endl;
            continue;
          }
          if (failure.empty()) failure = what;
          break;
        }
      }
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 0; t < std::min<unsigned>(opt.jobs, static_cast<unsigned>(list.size())); ++t)
    pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  return failure;
}

}  // namespace family
}  // namespace preadaptive_mrac
