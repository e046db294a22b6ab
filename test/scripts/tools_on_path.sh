#!/usr/bin/env bash
# the README's way. After `source build/devel/setup.bash` the batch tools are
# commands (catkin's global bin, devel/bin), with a link each in the package's lib/ for rosrun;
# preadapt_sim finds the package's config/ from where it is (no source path compiled in), from
# any working directory, and gives the same run as with the folder named explicitly.
# (The installed shape, with the source gone, and rosrun: test/scripts/catkin_workspace.sh.)
set -uo pipefail
TEST_NAME=tools_on_path
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
unset PREADAPTIVE_MRAC_CONFIG_DIR
W=$(mktemp -d /tmp/pmrac_tools_on_path.XXXXXX)
FAIL=0
fail() {
  echo "FAIL: $*"
  FAIL=1
}
libexec=$(catkin_find --without-underlays --libexec preadaptive_mrac 2>/dev/null | head -1)
for tool in preadapt_sim preadapt_sweep preadapt_family; do
  [ "$(command -v $tool)" = "$BUILD/devel/bin/$tool" ] ||
    fail "$tool is not a command after sourcing $BUILD/devel/setup.bash (command -v: '$(command -v $tool)')"
  [ -x "$libexec/$tool" ] || fail "$tool: no link in $libexec for rosrun"
  if grep -aq "$ROOT/config" "$BUILD/devel/bin/$tool" 2>/dev/null; then
    fail "$tool has the source's config path compiled in"
  fi
done
# rosrun finds every executable of the package after the README's own build
# (build/ inside the source, whose paths rosrun drops: cmake/install.cmake links them into
# .rosrun/), each at exactly one place (two would make rosrun ask which), and roslaunch's
# find_node still finds the nodes once. The executables: those of the devel space's
# lib/preadaptive_mrac but the tests and the benchmarks (bench_*, wakeup_floor), and launch_checked.
exes=$(find -L "$BUILD/devel/lib/preadaptive_mrac" -maxdepth 1 -type f -perm /111 -printf '%f\n' |
  grep -v -e '^test_' -e '^bench_controller$' -e '^wakeup_floor$' -e '^bench_jsbsim$' -e '^bench_bag_writer$' | sort)
n=0
for exe in $exes launch_checked; do
  found=$(cd / && rosrun --prefix echo preadaptive_mrac "$exe" </dev/null 2>&1)
  if [ "$(wc -l <<<"$found")" != 1 ] || [ ! -x "$found" ]; then
    fail "rosrun preadaptive_mrac $exe: $(head -3 <<<"$found" | paste -sd' ')"
  fi
  n=$((n + 1))
done
[ "$n" -ge 14 ] || fail "only $n executables found in $BUILD/devel/lib/preadaptive_mrac ($exes)"
for node in plant_sim_node mrac_controller_node run_monitor_node bag_recorder_node pmrac_manager; do
  /usr/bin/python3 -c 'import sys, roslib.packages as p
m = p.find_node("preadaptive_mrac", sys.argv[1])
sys.exit(0 if len(m) == 1 else "roslaunch finds %d: %s" % (len(m), m))' "$node" ||
    fail "roslaunch's find_node($node) is not one executable"
done
cd "$W" || exit 1
preadapt_sim --scenario 1 --mode rac --json >found.out 2>found.err || fail "preadapt_sim from $W: $(cat found.err)"
PREADAPTIVE_MRAC_CONFIG_DIR=$ROOT/config preadapt_sim --scenario 1 --mode rac --json >named.out 2>&1 ||
  fail "preadapt_sim with PREADAPTIVE_MRAC_CONFIG_DIR: $(tail -2 named.out)"
strip() { tail -1 "$1" | sed 's/"wall_time_s":[^,}]*//'; }
[ "$(strip found.out)" = "$(strip named.out)" ] || fail "the run differs with config/ found and named"
cd / || exit 1
if [ "$FAIL" = 0 ]; then
  echo "ok: preadapt_sim, preadapt_sweep, preadapt_family on PATH from the devel space, rosrun finds each of $n executables once, config/ found from the executable"
  echo "$TEST_NAME: PASSED"
  rm -rf "$W"
else
  echo "$TEST_NAME: FAILED (files in $W)"
fi
exit "$FAIL"
