#pragma once
/// \file setup.hpp
/// \brief What the batch CLI, the sweep tool and the ROS nodes share: locating the package's
/// config files, reading all sections with every problem at once, and the run's JSON summary.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "preadaptive_mrac/core/closed_loop.hpp"
#include "preadaptive_mrac/core/controller/controller.hpp"
#include "preadaptive_mrac/core/schema/params.hpp"
#include "preadaptive_mrac/core/sim/plant.hpp"
#include "preadaptive_mrac/core/sim/scenario.hpp"

namespace preadaptive_mrac {

/// \brief The package's config/ directory: $PREADAPTIVE_MRAC_CONFIG_DIR if set, else
/// share/preadaptive_mrac/config of the prefix (devel or install space) the running executable
/// is in, else "config" (relative to the working directory).
std::string configDir();
/// \brief "1" | "2" | "3" -> config/scenarios/scenarioN.yaml; anything else is a path.
std::string scenarioPath(const std::string& arg);
/// \brief Default plant and controller files.
std::string defaultPlantPath();
std::string defaultControllerPath();

/// \brief The longest run (every `until` of a scenario) and the most steps (the scenario's end
/// over the step), checked when a configuration is read, before a run allocates anything
/// (docs/reference/limits.md). A step recorded for --csv is about 350 bytes.
constexpr double kMaxRunSeconds = 86400.0;
constexpr long long kMaxRunSteps = 10000000;
/// \brief Why a run of `end_s` seconds at `dt` seconds a step is too long ("" when it is not,
/// or when either is not positive: those are refused by their own keys).
std::string runLengthProblem(double end_s, double dt);

/// \brief Every section a run needs, validated.
struct RunConfig {
  PlantConfig plant;
  ControllerConfig controller;
  Scenario scenario;
  /// "full name = value" of every optional key or section that was absent and defaulted
  /// (what a node logs at start-up, so no default is silent).
  std::vector<std::string> defaults_used;
  /// "full name = value (what from)" of every value computed at start in place of the given
  /// one (`controller.attention.thresholds: derived`); empty otherwise.
  std::vector<std::string> derived;
  /// K (CARE) and P (Lyapunov) of the design model (controller.model, else plant.A, plant.B),
  /// controller.Q and controller.R as read:
  /// validation solves them anyway, and a Controller built from this configuration can take
  /// them instead of solving again. Empty unless both sections were read.
  std::optional<ControllerDesign> design;
};

/// \brief Which sections to read (a plant node needs no controller, and so on).
struct Sections {
  bool plant = true, controller = true, scenario = true;
  /// Report top-level keys other than the three sections (the CLI: a --set typo);
  /// off for ROS, whose private namespaces also hold node parameters.
  bool strict_top_level = false;
};

/// \brief Read and validate the sections of `tree` (keys plant, controller, scenario), report
/// unknown keys inside them, and check the design (K from the CARE, P from the Lyapunov
/// equation) so that (A, B) not stabilisable etc. come back as problems naming the keys.
/// Throws ConfigError with every problem.
RunConfig readRunConfig(const ParamValue& tree, const KeyStyle& style = {}, Sections sections = {});

/// \brief `controller.attention.thresholds: derived`: c_e and c_ed of `rc->controller` from its
/// design model (rc->design), `controller.attention.command` and the noise on the tracked output
/// (`plant.noise.std`), in place of the given values, with a line each in `rc->derived`
/// (deriveAttentionThresholds). Nothing when `fixed` or without a design. readRunConfig calls it;
/// call it again after changing the plant's noise. Returns a problem with
/// `controller.attention.hysteresis` (not below the derived c_e), else "".
std::string deriveAttention(RunConfig* rc);

/// \brief Identification of a run for its JSON summary.
struct RunInfo {
  std::string scenario;  ///< as given (1|2|3|path)
  std::string mode;
  std::uint64_t seed = 0;
  double dt = 0.0;
  std::vector<std::string> overrides;
  double wall_time_s = 0.0;
  std::vector<std::string> defaults_used;  ///< optional keys filled with defaults
};

/// \brief The JSON summary of a run (keys in a fixed order).
/// \brief The first exit from the flight envelope as the JSON outputs give it (`null` for a run
/// that stayed inside): t, step, bound, key, value, limit, x, u_command, conditions (the
/// plant's conditions record by name), non_finite, non_finite_t, text (one line).
nlohmann::ordered_json envelopeExitJson(const EnvelopeExit& x);
nlohmann::ordered_json runSummary(const RunInfo& info, const Controller& ctl, const SimResult& res);
/// \brief One-line JSON summary of a run (the `--json` output and one sweep line).
std::string runSummaryJson(const RunInfo& info, const Controller& ctl, const SimResult& res);
/// \brief A scenario as the YAML that Scenario::read reads back (17 significant digits).
std::string scenarioToYaml(const Scenario& s);
/// \brief Write the time series as CSV (t, x, x_r, e, e_dot_est, u, theta_hat, theta_true, phase).
void writeSeriesCsv(const std::string& path, const Series& s);

}  // namespace preadaptive_mrac
