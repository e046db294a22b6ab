/// \file preadapt_margins.cpp
/// \brief Robustness margins of one mode on one scenario, measured by simulation: the
/// time-delay margin and the gain (elevator effectiveness) margins, as one JSON line.

#include <cmath>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_common.hpp"
#include "preadaptive_mrac/core/controller/mode_registry.hpp"
#include "preadaptive_mrac/core/margins.hpp"

using namespace preadaptive_mrac;

namespace {
const char* kAbout =
    "Robustness margins by simulation: the largest plant.actuator.delay (bisection on whole "
    "samples over [0, --max-delay], to --delay-resolution) and the smallest and largest constant "
    "elevator effectiveness Lambda (bisection over [--min-effectiveness, 1] and [1, "
    "--max-effectiveness]) at which every window's peak |e| stays within --bound and everything "
    "stays finite (a run is stopped at the first sample beyond the bound). Every other key is "
    "the configuration as given (--set, --plant, ...). Prints one JSON line. Exit code 2 on bad "
    "input.";

nlohmann::ordered_json searchJson(const MarginSearch& s, const char* unit) {
  nlohmann::ordered_json j;
  j["status"] = s.status;
  // NaN (not searched, or no unstable value found) is null.
  const auto value = [](double v) { return std::isnan(v) ? nlohmann::json() : nlohmann::json(v); };
  j[std::string("stable_") + unit] = value(s.stable);
  j[std::string("unstable_") + unit] = value(s.unstable);
  j["runs"] = s.runs;
  return j;
}

double positive(const std::string& flag, const std::string& text) {
  const double v = cli::parseDouble(flag, text);
  if (!(v > 0.0)) throw cli::UsageError(flag + ": must be > 0, got " + text);
  return v;
}
}  // namespace

int main(int argc, char** argv) {
  return cli::runTool("preadapt_margins", [&]() -> int {
    cli::RunRequest req;
    MarginOptions opt;
    CLI::App app{kAbout, "preadapt_margins"};
    cli::RunOptionText text;
    std::string mode, seed, bound, max_delay, delay_res, min_eff, max_eff, eff_res;
    cli::addRunOptions(app, &req, &text, true);
    cli::addText(app, "--mode", &mode, modeNames(" | "));
    cli::addText(app, "--seed", &seed, "seed of the network's initial weights");
    cli::addText(app, "--bound", &bound, "peak |e| bound of every window [rad] (default 0.2)");
    cli::addText(app, "--max-delay", &max_delay, "top of the delay interval [s] (default 2.0)");
    cli::addText(app, "--delay-resolution", &delay_res, "delay bracket width [s] (default 0.004)");
    cli::addText(app, "--min-effectiveness", &min_eff,
                 "bottom of the lower gain interval (default 0.01)");
    cli::addText(app, "--max-effectiveness", &max_eff,
                 "top of the upper gain interval, <= 2 (default 2)");
    cli::addText(app, "--effectiveness-resolution", &eff_res,
                 "Lambda bracket width (default 0.01)");
    if (!cli::parseCommandLine(app, argc, argv)) return 0;
    if (app.count("--scenario") == 0)
      throw cli::UsageError("--scenario is required (1, 2, 3 or a YAML path)");
    cli::finishRunOptions(text, &req);
    if (app.count("--mode")) req.mode = mode;
    if (app.count("--seed")) req.seed = cli::parseSeed("--seed", seed);
    if (!bound.empty()) opt.bound = positive("--bound", bound);
    if (!max_delay.empty()) opt.max_delay = positive("--max-delay", max_delay);
    if (!delay_res.empty()) opt.delay_resolution = positive("--delay-resolution", delay_res);
    if (!min_eff.empty()) opt.min_effectiveness = positive("--min-effectiveness", min_eff);
    if (!max_eff.empty()) opt.max_effectiveness = positive("--max-effectiveness", max_eff);
    if (!eff_res.empty())
      opt.effectiveness_resolution = positive("--effectiveness-resolution", eff_res);
    if (opt.max_delay > kMaxDelay)
      throw cli::UsageError("--max-delay: must be at most " + formatNumber(kMaxDelay) + " s");
    if (!(opt.min_effectiveness < 1.0))
      throw cli::UsageError("--min-effectiveness: must be < 1, got " + min_eff);
    if (!(opt.max_effectiveness > 1.0 && opt.max_effectiveness <= 2.0))
      throw cli::UsageError("--max-effectiveness: must be in (1, 2], got " + max_eff);

    const cli::PreparedRun run = cli::prepare(req);
    // One controller is built (K and P solved once); every run starts from a copy of it.
    const std::unique_ptr<Controller> proto = cli::makeController(run);
    const ControllerFactory make = [&]() { return std::make_unique<Controller>(*proto); };
    const double dt = run.cfg.controller.sample_time;
    const MarginsResult m = findMargins(run.cfg.plant, run.cfg.scenario, dt, make, opt);

    nlohmann::ordered_json j;
    j["scenario"] = run.info.scenario;
    j["mode"] = run.info.mode;
    j["seed"] = run.info.seed;
    j["dt"] = dt;
    j["overrides"] = run.info.overrides;
    j["bound"] = opt.bound;
    j["delay_interval"] = {0.0, opt.max_delay};
    j["delay_resolution"] = opt.delay_resolution;
    j["effectiveness_interval"] = {opt.min_effectiveness, opt.max_effectiveness};
    j["effectiveness_resolution"] = opt.effectiveness_resolution;
    j["nominal_stable"] = m.nominal_stable;
    j["nominal_peak_abs_e"] = m.nominal.peak_abs_e;
    nlohmann::ordered_json peaks = nlohmann::json::array();
    for (const auto& w : m.nominal.windows) peaks.push_back(w.peak_abs_e);
    j["nominal_window_peaks"] = peaks;
    j["delay_margin"] = searchJson(m.delay, "s");
    j["gain_margin_low"] = searchJson(m.effectiveness_low, "lambda");
    j["gain_margin_high"] = searchJson(m.effectiveness_high, "lambda");
    j["runs"] = m.runs;
    std::cout << j.dump() << std::endl;
    return 0;
  });
}
