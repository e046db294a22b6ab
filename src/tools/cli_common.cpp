#include "cli_common.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>

#include "preadaptive_mrac/core/controller/mode_registry.hpp"
#include "preadaptive_mrac/io/weights_io.hpp"
#include "preadaptive_mrac/io/yaml_params.hpp"

namespace preadaptive_mrac {
namespace cli {

int runTool(const char* tool, const std::function<int()>& body) {
  try {
    return body();
  } catch (const UsageError& e) {
    std::cerr << tool << ": error: " << e.what() << std::endl;
    return 2;
  } catch (const std::exception& e) {
    std::cerr << tool << ": error: " << e.what() << std::endl;
    return 1;
  }
}

CLI::Option* addText(CLI::App& app, const std::string& name, std::string* out,
                     const std::string& help) {
  return app.add_option(name, *out, help)->expected(1)->type_name("TEXT");
}

CLI::Option* addTexts(CLI::App& app, const std::string& name, std::vector<std::string>* out,
                      const std::string& help) {
  return app.add_option(name, *out, help)
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->type_name("TEXT");
}

void addRunOptions(CLI::App& app, RunRequest* req, RunOptionText* text, bool with_scenario) {
  if (with_scenario)
    addText(app, "--scenario", &req->scenario, "1, 2, 3 or the path of a scenario YAML");
  addText(app, "--dt", &text->dt, "sample time = integration step [s] (default: the YAML's)");
  addTexts(app, "--set", &req->sets,
           "key=value override of a dotted YAML path, e.g. controller.attention.c_e=0.01 "
           "(repeatable)");
  addText(app, "--plant", &req->plant_path, "plant YAML (default config/plant/b747.yaml)");
  addText(app, "--controller", &req->controller_path,
          "controller YAML (default config/controller/default.yaml)");
}

void finishRunOptions(const RunOptionText& text, RunRequest* req) {
  if (!text.dt.empty()) req->dt = parseDouble("--dt", text.dt);
}

bool parseCommandLine(CLI::App& app, int argc, char** argv) {
  app.allow_extras(true);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return false;
  } catch (const CLI::ArgumentMismatch& e) {
    // "--seed" without its value: name the flag as the old parser did.
    std::string flag = e.what();
    flag = flag.substr(0, flag.find_first_of(": "));
    throw UsageError(flag + ": missing value");
  } catch (const CLI::ParseError& e) {
    throw UsageError(e.what());
  }
  const auto extra = app.remaining();
  if (!extra.empty()) throw UsageError("unknown argument '" + extra.front() + "' (see --help)");
  return true;
}

double parseDouble(const std::string& flag, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end == text.c_str() || *end != '\0' || !std::isfinite(v))
    throw UsageError(flag + ": expected a finite number, got '" + text + "'");
  return v;
}

std::uint64_t parseSeed(const std::string& flag, const std::string& text) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
    throw UsageError(flag + ": expected a non-negative integer, got '" + text + "'");
  try {
    return std::stoull(text);
  } catch (const std::exception&) {
    throw UsageError(flag + ": integer out of range: '" + text + "'");
  }
}

int parseCount(const std::string& flag, const std::string& text, int max) {
  const std::string bad =
      flag + ": expected a whole number in 1.." + std::to_string(max) + ", got '" + text + "'";
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
    throw UsageError(bad);
  // Leading zeros dropped, so that the length bounds the value before stoull can overflow.
  const size_t first = text.find_first_not_of('0');
  if (first == std::string::npos || text.size() - first > 10) throw UsageError(bad);
  const auto v = std::stoull(text.substr(first));
  if (v > static_cast<std::uint64_t>(max)) throw UsageError(bad);
  return static_cast<int>(v);
}

std::vector<std::string> splitTopLevel(const std::string& text) {
  std::vector<std::string> out;
  std::string cur;
  int depth = 0;
  for (char c : text) {
    if (c == '[' || c == '{') ++depth;
    if (c == ']' || c == '}') --depth;
    if (c == ',' && depth == 0) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

std::string withEffort(const std::string& json, const RunMetrics& m) {
  nlohmann::ordered_json e;
  e["peak_abs_u"] = m.effort.peak_abs_u;
  e["time_at_travel_limit"] = m.effort.time_at_travel;
  e["time_at_rate_limit"] = m.effort.time_at_rate;
  e["steady_tv"] = m.effort.steady_tv;
  e["steady_fraction"] = EffortMetrics::kSteadyFraction;
  e["window_time_at_limit"] = nlohmann::ordered_json::array();
  e["window_steady_tv"] = nlohmann::ordered_json::array();
  for (const auto& w : m.windows) {
    e["window_time_at_limit"].push_back(w.time_at_limit);
    e["window_steady_tv"].push_back(w.steady_tv);
  }
  const size_t close = json.find_last_of('}');
  if (close == std::string::npos) return json;
  return json.substr(0, close) + ",\"effort\":" + e.dump() + json.substr(close);
}

std::string elevatorPresetPath(const std::string& flag, const std::string& preset) {
  const std::string path = preset == "b747" ? configDir() + "/plant/elevator_b747.yaml" : preset;
  if (std::ifstream(path).good()) return path;
  throw UsageError(flag +
                   ": expected b747, ideal or the path of a plant YAML with a "
                   "plant.actuator section; no file '" +
                   path + "'");
}

PreparedRun prepare(const RunRequest& req) {
  PreparedRun run;
  ParamValue tree = ParamValue::makeMap();
  const std::string plant = req.plant_path.empty() ? defaultPlantPath() : req.plant_path;
  const std::string controller =
      req.controller_path.empty() ? defaultControllerPath() : req.controller_path;
  try {
    tree.merge(loadYamlFile(plant));
    for (const auto& p : req.plant_presets) tree.merge(loadYamlFile(p));
    tree.merge(loadYamlFile(controller));
    try {
      tree.merge(loadYamlFile(scenarioPath(req.scenario)));
    } catch (const FileError& e) {
      throw UsageError("--scenario: expected 1, 2, 3 or the path of a scenario YAML; " +
                       std::string(e.what()));
    }
    for (const auto& s : req.sets) applyOverride(&tree, s);
  } catch (const FileError& e) {
    throw UsageError(e.what());
  }
  if (req.mode) {
    if (findMode(*req.mode) == nullptr)
      throw UsageError("--mode: unknown mode '" + *req.mode + "' (expected " +
                       modeNames(", ", " or ") + ")");
    tree.setPath("controller.mode", ParamValue::makeString(*req.mode));
  }
  if (req.seed)
    tree.setPath("controller.preadaptation.seed",
                 ParamValue::makeInt(static_cast<std::int64_t>(*req.seed)));
  if (req.dt) {
    if (!(*req.dt > 0.0)) throw UsageError("--dt: must be > 0, got " + std::to_string(*req.dt));
    tree.setPath("controller.sample_time", ParamValue::makeDouble(*req.dt));
  }
  Sections sections;
  sections.strict_top_level = true;
  try {
    run.cfg = readRunConfig(tree, KeyStyle{}, sections);
  } catch (const ConfigError& e) {
    std::string line;
    for (const auto& p : e.problems()) line += (line.empty() ? "" : "; ") + p;
    throw UsageError("invalid configuration: " + line);
  }
  // Values computed at start in place of the given ones: on stderr, so a --json line is the same.
  for (const auto& d : run.cfg.derived) std::fprintf(stderr, "derived at start: %s\n", d.c_str());
  if (!req.weights_in.empty()) {
    try {
      run.weights = loadWeights(req.weights_in, run.cfg.controller.hidden, run.cfg.plant.n());
    } catch (const WeightsError& e) {
      throw UsageError(std::string("--weights-in: ") + e.what());
    }
  }
  run.info.scenario = req.scenario;
  run.info.mode = run.cfg.controller.mode;
  run.info.seed = run.cfg.controller.seed;
  run.info.dt = run.cfg.controller.sample_time;
  run.info.overrides = req.sets;
  run.info.defaults_used = run.cfg.defaults_used;
  return run;
}

std::unique_ptr<Controller> makeController(const PreparedRun& run) {
  // K and P were solved when the configuration was validated: not again.
  const DesignModel model = designModelOf(run.cfg.plant, run.cfg.controller);
  auto ctl = run.cfg.design
                 ? std::make_unique<Controller>(model, run.cfg.controller, *run.cfg.design)
                 : std::make_unique<Controller>(model, run.cfg.controller);
  if (run.weights) ctl->setNetwork(*run.weights);
  return ctl;
}

SimResult execute(const PreparedRun& run, bool record_series,
                  std::unique_ptr<Controller>* controller) {
  auto ctl = makeController(run);
  ClosedLoop loop(run.cfg.plant, run.cfg.scenario, ctl.get());
  SimOptions opt;
  opt.dt = run.cfg.controller.sample_time;
  opt.record_series = record_series;
  SimResult res = loop.run(opt);
  if (controller) *controller = std::move(ctl);
  return res;
}

std::string envelopeNote(const EnvelopeExit& x) {
  if (!x.exited) return "";
  return "left the flight envelope at " + x.describe() +
         (x.non_finite ? "; the run ended there (a state or command that is not finite)"
                       : "; the run went on to its end (docs/reliability.md)");
}

}  // namespace cli
}  // namespace preadaptive_mrac
