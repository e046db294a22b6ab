/// \file preadapt_sim.cpp
/// \brief Batch simulator: one closed-loop run, no ROS master.

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "aircraft_elevator.hpp"
#include "cli_common.hpp"
#include "preadaptive_mrac/core/controller/mode_registry.hpp"
#include "preadaptive_mrac/io/weights_io.hpp"

using namespace preadaptive_mrac;

int main(int argc, char** argv) {
  cli::RunRequest req;
  std::string csv, weights_out;
  bool json = false;
  return cli::runTool("preadapt_sim", [&]() -> int {
    CLI::App app{
        "Batch simulator: plant + controller in closed loop, no ROS master. Keys for --set are "
        "dotted YAML paths, e.g. controller.attention.c_e=0.01 or scenario.reference.0.r=0.05. "
        "Exit code 2 on bad input, with one line naming what is wrong.",
        "preadapt_sim"};
    cli::RunOptionText text;
    std::string mode, seed;
    cli::addRunOptions(app, &req, &text, true);
    cli::addText(app, "--mode", &mode, modeNames(" | "));
    cli::addText(app, "--seed", &seed, "seed of the network's initial weights");
    cli::addText(app, "--csv", &csv, "write the time series to this CSV file");
    app.add_flag("--json", json, "print one JSON summary line (the last line)");
    cli::addText(app, "--weights-in", &req.weights_in, "load network weights and regimes");
    std::string elevator;
    cli::addText(app, "--elevator", &elevator,
                 "b747 (config/plant/elevator_b747.yaml, the aircraft's travel and rate) or a "
                 "YAML path, merged over the plant file, or ideal (the plant file's own); "
                 "default: b747 with plant.engine jsbsim, else the plant file's own elevator "
                 "(config/plant/b747.yaml: unlimited, as in the paper)");
    cli::addText(app, "--weights-out", &weights_out,
                 "save network weights and regimes (a file that exists is kept: exit 2, unless "
                 "it is --weights-in or --force is given)");
    bool force = false;
    app.add_flag("--force", force, "replace an existing --weights-out file");
    bool list_modes = false;
    app.add_flag("--list-modes", list_modes,
                 "print the registered modes, one 'name<TAB>doc' line each, and exit");
    if (!cli::parseCommandLine(app, argc, argv)) return 0;
    if (list_modes) {  // the one list, for the Python package, the docs and their test
      for (const ModeEntry& m : modeRegistry()) std::cout << m.name << '\t' << m.doc << '\n';
      return 0;
    }
    if (app.count("--scenario") == 0)
      throw cli::UsageError("--scenario is required (1, 2, 3 or a YAML path)");
    std::error_code ec;
    if (!force && !weights_out.empty() && std::filesystem::exists(weights_out, ec) &&
        !(!req.weights_in.empty() && std::filesystem::equivalent(weights_out, req.weights_in, ec)))
      throw cli::UsageError("--weights-out: '" + weights_out +
                            "' exists: not replaced (remove it, name a new file, or --force)");
    cli::finishRunOptions(text, &req);
    if (!elevator.empty() && elevator != "ideal")
      req.plant_presets.push_back(cli::elevatorPresetPath("--elevator", elevator));
    if (app.count("--mode")) req.mode = mode;
    if (app.count("--seed")) req.seed = cli::parseSeed("--seed", seed);

    cli::PreparedRun run = cli::prepare(req);
    // The JSBSim aircraft is beyond the paper: it flies the aircraft's elevator unless told.
    if (elevator.empty() && run.cfg.plant.engine == PlantEngineKind::kJsbsim) {
      cli::addAircraftElevator(run.cfg.plant, &req, "preadapt_sim", false);
      run = cli::prepare(req);
    }
    const auto t0 = std::chrono::steady_clock::now();
    std::unique_ptr<Controller> ctl;
    SimResult res = cli::execute(run, !csv.empty(), &ctl);
    run.info.wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    // Said once, on stderr, whatever else is printed (the JSON line carries it as well).
    if (res.envelope_exit.exited)
      std::cerr << "preadapt_sim: " << cli::envelopeNote(res.envelope_exit) << std::endl;
    if (!csv.empty()) writeSeriesCsv(csv, res.series);
    if (!weights_out.empty()) saveWeights(weights_out, ctl->network().state());
    if (json) {
      std::cout << cli::withEffort(runSummaryJson(run.info, *ctl, res), res.metrics) << std::endl;
    } else {
      std::printf("scenario %s, mode %s, seed %llu, dt %g s: %lld steps in %.3f s\n",
                  run.info.scenario.c_str(), run.info.mode.c_str(),
                  static_cast<unsigned long long>(run.info.seed), run.info.dt,
                  static_cast<long long>(res.steps), run.info.wall_time_s);
      std::printf("%-8s %-8s %-10s %-12s %-12s %s\n", "t_start", "t_end", "theta0", "peak|e|",
                  "IAE", "recovery[s]");
      for (const auto& w : res.metrics.windows)
        std::printf("%-8.2f %-8.2f %-10.3g %-12.5g %-12.5g %s\n", w.t_start, w.t_end,
                    w.theta.size() ? w.theta[0] : 0.0, w.peak_abs_e, w.iae,
                    w.recovery_time >= 0 ? std::to_string(w.recovery_time).c_str() : "-");
      if (!run.cfg.defaults_used.empty()) {
        std::string line;
        for (const auto& d : run.cfg.defaults_used) line += (line.empty() ? "" : ", ") + d;
        std::printf("optional keys filled with defaults: %s\n", line.c_str());
      }
      std::printf("events: %zu; IAE %.6g rad s, peak |e| %.6g rad, max |u| %.6g rad\n",
                  res.events.size(), res.metrics.iae, res.metrics.peak_abs_e,
                  res.metrics.max_abs_u);
      const EffortMetrics& ef = res.metrics.effort;
      std::printf(
          "elevator effort: peak |u| applied %.6g rad, %.4g s at the travel limit, %.4g s at the "
          "rate limit, steady-flight total variation %.6g rad (last %g of each window)\n",
          ef.peak_abs_u, ef.time_at_travel, ef.time_at_rate, ef.steady_tv,
          EffortMetrics::kSteadyFraction);
    }
    return 0;
  });
}
