#pragma once
/// \file cli_common.hpp
/// \brief What preadapt_sim and preadapt_sweep share: loading the layered YAML, applying
/// overrides and flags, running one closed loop, and usage errors (exit code 2).

#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "preadaptive_mrac/io/setup.hpp"

namespace preadaptive_mrac {
namespace cli {

/// \brief Bad command line or input; the tool prints it on one line and exits with code 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// \brief A batch tool's main(): runs `body` and returns its exit code; a UsageError is
/// printed as "<tool>: error: <what>" and gives 2, any other exception the same line and 1.
int runTool(const char* tool, const std::function<int()>& body);

/// \brief One run as the command line describes it.
struct RunRequest {
  std::string scenario = "1";
  std::string plant_path;                  ///< empty: the package's config/plant/b747.yaml
  std::vector<std::string> plant_presets;  ///< YAML merged over the plant file, in order
  std::string controller_path;             ///< empty: config/controller/default.yaml
  std::optional<std::string> mode;
  std::optional<std::uint64_t> seed;
  std::optional<double> dt;
  std::vector<std::string> sets;  ///< key=value, applied after the files, before the flags
  std::string weights_in;
};

/// \brief A run ready to go: validated configuration and its identification.
struct PreparedRun {
  RunConfig cfg;
  RunInfo info;
  std::optional<LearnedState> weights;  ///< from weights_in
};

/// \brief Load files, apply --set and flags, validate everything. Throws UsageError.
PreparedRun prepare(const RunRequest& req);
/// \brief The controller of a prepared run (its weights loaded), before any step.
std::unique_ptr<Controller> makeController(const PreparedRun& run);
/// \brief Run the closed loop; `controller` receives the controller (for its final network).
SimResult execute(const PreparedRun& run, bool record_series,
                  std::unique_ptr<Controller>* controller);

/// \brief The flags every tool shares, as text until finishRunOptions() checks them.
struct RunOptionText {
  std::string dt;
};
/// \brief The one line a batch tool says about a run that left the flight envelope ("" for
/// one that stayed inside): "left the flight envelope at t = ...: <bound>; the run went on to
/// its end" (a finite excursion) or "...; the run ended there (a state or command that is not
/// finite)".
std::string envelopeNote(const EnvelopeExit& x);

/// \brief Add --dt, --set, --plant, --controller (and --scenario when `with_scenario`) to a
/// CLI11 app, bound to `req`.
void addRunOptions(CLI::App& app, RunRequest* req, RunOptionText* text, bool with_scenario);
/// \brief Check what addRunOptions() bound (--dt a finite number). Throws UsageError.
void finishRunOptions(const RunOptionText& text, RunRequest* req);
/// \brief An option whose value is a text that the tool checks itself (one value, repeatable
/// only when `repeat`); CLI11 does the parsing, the tool the messages.
CLI::Option* addText(CLI::App& app, const std::string& name, std::string* out,
                     const std::string& help);
CLI::Option* addTexts(CLI::App& app, const std::string& name, std::vector<std::string>* out,
                      const std::string& help);
/// \brief Parse argv. Returns true when the tool should go on; false after printing the
/// generated --help (exit code 0). Any parse problem throws UsageError with one line in this
/// package's words ("unknown argument '--x' (see --help)", "--seed: missing value").
bool parseCommandLine(CLI::App& app, int argc, char** argv);

/// \brief A run's JSON summary line with the elevator effort (closed_loop.hpp EffortMetrics)
/// added as its last key, "effort": {peak_abs_u, time_at_travel_limit, time_at_rate_limit,
/// steady_tv, steady_fraction, window_time_at_limit [s], window_steady_tv [rad]}; the keys
/// before it unchanged byte for byte.
std::string withEffort(const std::string& json, const RunMetrics& m);

/// \brief The path of an elevator preset: "b747" is config/plant/elevator_b747.yaml, anything
/// else a YAML path; throws UsageError naming `flag` when the file does not exist.
std::string elevatorPresetPath(const std::string& flag, const std::string& preset);

double parseDouble(const std::string& flag, const std::string& text);
std::uint64_t parseSeed(const std::string& flag, const std::string& text);
/// \brief A count (scenarios, regimes, threads): a whole number in 1..max. Throws UsageError
/// naming `flag` on 0, a negative number, one over `max` or anything that is not a number.
int parseCount(const std::string& flag, const std::string& text, int max);
/// \brief Split on commas that are not inside brackets ("0.1,[1,2,3]" -> 2 items).
std::vector<std::string> splitTopLevel(const std::string& text);

}  // namespace cli
}  // namespace preadaptive_mrac
