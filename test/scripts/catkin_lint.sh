#!/usr/bin/env bash
# catkin_lint (Debian package catkin-lint) on a workspace holding the package, as a user lints
# their own (ws/src/preadaptive_mrac):
#   -W1 (what `catkin_lint -W1` shows by default to a user): nothing at all;
#   -W2: nothing but the notices explained below;
#   and the executables left out of the install space must be exactly the development ones
#   listed here (cmake/install.cmake turns catkin_lint's uninstalled_script and
#   uninstalled_target warnings off for the package; --show-ignored still lists them, and a
#   new script for users must be installed in cmake/install.cmake, a new development script
#   added below with its reason).
set -uo pipefail
TEST_NAME=catkin_lint
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
command -v catkin_lint >/dev/null || {
  echo "SKIPPED: $TEST_NAME: catkin_lint not installed (apt-get install catkin-lint)"
  exit 77
}
# Ignored, with the reason:
#   literal_project_name  target names spell the package out (preadaptive_mrac_core, ...):
#                         readable and grep-able, and the package is not renamed
#   unsorted_list         source and target lists are in reading (dependency) order
#   global_var_collision  CMAKE_BUILD_TYPE, PYTHON_EXECUTABLE and Python3_EXECUTABLE are
#                         CMake's own, set on purpose (CMakeLists.txt says why); the options
#                         carry the package's prefixes PMRAC_ / PREADAPTIVE_MRAC_
IGNORE=(literal_project_name unsorted_list global_var_collision)
# Executables left out of the install space on purpose: development tools that expect a
# source checkout (the benchmarks, the test and CI drivers, the studies, fuzzing, Slurm, the
# JSBSim install into the build folder, the JSBSim protocol probe and its scenario timing).
DEV_SCRIPTS="bench/bag_vs_cli.py bench/perf_report.py bench/prototype_rac.py bench/ros_bench.sh
bench/run_bench.sh bench/jsbsim_scenario1.sh scripts/check_format scripts/config_mutation_study
scripts/fuzz scripts/install_deps scripts/junit_wrap scripts/noise_study scripts/python_files
scripts/reproduction_study scripts/robust_study scripts/regime_effectiveness_study
scripts/switch_reaction_study scripts/l1_reference_margin_study scripts/core_includes
scripts/check_baseline_identical scripts/run_demo scripts/slurm/submit_sweep
scripts/slurm/sweep_array.sbatch scripts/two_machines_env.sh scripts/test scripts/summarize_tests
scripts/install_jsbsim jsbsim/tools/jsbsim_probe.py scripts/code_sizes"
DEV_TARGETS="bench_controller wakeup_floor bench_jsbsim bench_bag_writer"

WS=$(mktemp -d /tmp/pmrac_catkin_lint.XXXXXX)
trap 'rm -rf "$WS"' EXIT
mkdir -p "$WS/src"
ln -s "$ROOT" "$WS/src/preadaptive_mrac"
# Lines every run prints: the summary, and no rosdep database offline (system dependency keys
# cannot be checked here; `rosdep update` on a user's machine).
chatter() {
  case "$1" in
    "" | "catkin_lint: checked "* | "catkin_lint: "*" messages have been ignored"* | \
      "catkin_lint: option -W2 will show"* | "catkin_lint: cannot load rosdep database"* | \
      "catkin_lint: unknown dependencies will be ignored") return 0 ;;
  esac
  return 1
}
FAIL=0
while IFS= read -r line; do
  chatter "$line" && continue
  echo "FAIL: -W1: $line"
  FAIL=1
done <<<"$(cd "$WS" && catkin_lint -W1 src 2>&1)"

args=(-W2)
for id in "${IGNORE[@]}"; do args+=(--ignore "$id"); done
while IFS= read -r line; do
  chatter "$line" && continue
  echo "FAIL: -W2: $line"
  FAIL=1
done <<<"$(cd "$WS" && catkin_lint "${args[@]}" src 2>&1)"

# The executables left out of the install space (reported with --show-ignored only).
while IFS= read -r line; do
  script=$(sed -n "s/.*warning: file '\(.*\)' is executable but not installed/\1/p" <<<"$line")
  target=$(sed -n "s/.*warning: target '\(.*\)' is not installed/\1/p" <<<"$line")
  [ -z "$script" ] && [ -z "$target" ] && continue
  if [ -n "$script" ] && grep -qw -- "$script" <<<"$DEV_SCRIPTS"; then continue; fi
  # Build outputs git ignores (build_fuzz/ of the fuzz smoke test, out/): not the package's files.
  if [ -n "$script" ] && git -C "$ROOT" check-ignore -q -- "$script" 2>/dev/null; then continue; fi
  if [ -n "$target" ] && grep -qw -- "$target" <<<"$DEV_TARGETS"; then continue; fi
  echo "FAIL: not installed and not a development tool listed here: $line"
  FAIL=1
done <<<"$(cd "$WS" && catkin_lint -W2 --show-ignored src 2>&1)"
if [ "$FAIL" = 0 ]; then
  echo "ok: catkin_lint -W1 on a workspace says nothing; -W2 only the explained notices; uninstalled: only the development executables"
  echo "$TEST_NAME: PASSED"
else
  echo "$TEST_NAME: FAILED"
fi
exit "$FAIL"
