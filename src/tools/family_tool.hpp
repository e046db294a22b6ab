#pragma once
/// \file family_tool.hpp
/// \brief preadapt_family's four steps: parse the command line (preadapt_family.cpp), draw the
/// scenarios and their runs (family_draw.cpp), run them on a thread pool (family_run.cpp) and
/// report each mode against rac (family_report.cpp).

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cli_common.hpp"
#include "preadaptive_mrac/core/sim/scenario_family.hpp"

namespace preadaptive_mrac {
namespace family {

/// \brief What the command line asks for, checked (every flag's own range; what needs the
/// plant's configuration is checked by drawFamily()).
struct Options {
  cli::RunRequest base;  ///< the files, --set and the fixed conditions every run shares
  std::uint64_t seed = 0;
  int count = 30;
  std::vector<std::string> modes;  ///< rac first
  double noise = 0.0;              ///< --noise: std on alpha and q (0: none)
  bool noise_given = false;        ///< --noise given (else a --set noise gets noise_seed)
  FamilySpec spec;
  std::string out_dir;  ///< empty: write no scenario files nor runs.jsonl
  bool json = false;
  bool force = false;  ///< --force: replace an earlier family's files in out_dir
  unsigned jobs = 1;
  std::string elevator = "b747";
  double trim_fraction = 0.5;
  bool every_regime = false;           ///< --trim-fraction none
  double quiet_factor = kQuietFactor;  ///< --quiet-factor (0: every window judged)
  std::string conditions;              ///< the plant conditions as the report's line names them
  ConditionRange delay, lag, gust, lambda_range;  ///< drawn per scenario (per regime: Lambda)
  bool turbulence = false;                        ///< --turbulence given
  std::optional<double> lambda;                   ///< one Lambda for every scenario
  std::optional<double> mismatch;                 ///< --mismatch given (0 included)
  std::optional<FaultRanges> faults;
};

/// \brief One run of the family: a mode on a scenario, and what it gave.
struct Job {
  int scenario = 0;
  std::string mode;
  RunConfig cfg;
  RunDigest digest;
  std::string json;   ///< its runs.jsonl line without the revisits (with --out-dir)
  EnvelopeExit exit;  ///< the run's first exit from the flight envelope (exited false: none)
};

/// \brief The lowest and highest value drawn of each condition over the family, by name.
using Span = std::map<std::string, std::pair<double, double>>;

/// \brief The family drawn: every scenario's runs and what the report needs of the draws.
struct Family {
  cli::PreparedRun prepared;  ///< the files and overrides, validated once
  std::optional<TrimCheck> trim;
  int rejected = 0;                           ///< regimes drawn again (trim infeasible)
  std::vector<std::vector<bool>> repeated;    ///< each scenario's repeated-switch windows
  std::vector<std::vector<bool>> quiet;       ///< each scenario's quiet windows (the report's)
  std::vector<nlohmann::ordered_json> drawn;  ///< each scenario's drawn_conditions
  Span span;
  std::vector<Job> jobs;  ///< scenario by scenario, the modes in order within each
};

/// \brief Parse and check the command line; false after printing --help. Throws
/// cli::UsageError.
bool parseOptions(int argc, char** argv, Options* opt);
/// \brief Validate the files against the flags, then draw every scenario, its conditions and
/// its runs (writing scenario_K.yaml with --out-dir). Throws cli::UsageError.
Family drawFamily(const Options& opt);
/// \brief Run every job on opt.jobs threads; the first failure's message ("" when none).
std::string runFamily(const Options& opt, Family* family);
/// \brief Each scenario's quiet windows (quietWindows) from its rac run: the sensor noise on the
/// measured output, the run's sample time and opt.quiet_factor.
void markQuietWindows(const Options& opt, Family* family);
/// \brief runs.jsonl (with --out-dir), the summary lines, each mode's table row and (--json)
/// JSON line, on stdout.
void reportFamily(const Options& opt, const Family& family);

}  // namespace family
}  // namespace preadaptive_mrac
