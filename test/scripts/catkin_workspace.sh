#!/usr/bin/env bash
# The package as a ROS user has it, from the README's own commands:
#   - the README's catkin block, run line by line in a workspace at ~/catkin_ws where HOME is a
#     scratch folder whose path makes ~/catkin_ws 40 characters or longer (a user's home):
#     `catkin_make` with testing on, as a user types it (the rostest targets' names must fit a
#     file name there), then `catkin_make run_tests_preadaptive_mrac_<...>` for a named subset
#     (one gtest, one rostest whose registration names a test plant) and catkin_test_results;
#     the README's `rosdep install` line is left out (it needs the network for rosdep's
#     database; package.xml is checked by catkin_lint.sh);
#   - `catkin_make install`;
#   - the README's catkin-tools line, `catkin build`, in the same workspace after its
#     catkin_make build and devel spaces are removed (catkin build refuses them), and
#     preadapt_sim from its devel space;
#   - then the source, build and devel spaces removed; from catkin_make's install space alone:
#   - the batch tools are on PATH and rosrun finds preadapt_sim; every executable is in
#     lib/preadaptive_mrac (where rosrun and roslaunch look); preadapt_sim finds its
#     configuration (no source path compiled in) and runs scenario 1 (rac and pa_learn);
#   - two lockstep runs of scenario.launch at once, each included in a namespace of its own
#     (run_a: rac in the nodelet shape, run_b: pa_learn in the process shape), recording: both
#     complete, and each bag equals its own batch CLI run bit for bit (bench/bag_vs_cli.py
#     --tol 0), with its tf under its namespace (not /tf), no controller gone stale and no
#     /use_sim_time set; the installed analyze_bag (and so the Python package) reads one bag;
#   - at the same time compare.launch in run_c (nodelet shape, rac and pa_learn), whose pairs
#     reach its manager, recorder and tf through the installed scripts/lib/parent_names: both
#     pairs' data in its bag equal their CLI runs bit for bit.
# The builds are the cost: ccache is used when present, through CMAKE_<LANG>_COMPILER_LAUNCHER
# in the environment (the user's command stays as written) and CCACHE_BASEDIR, so a new
# workspace still hits the cache and catkin build, in the same folders, hits catkin_make's
# objects. PMRAC_WS_KEEP=1 keeps the workspace.
set -uo pipefail
TEST_NAME=catkin_workspace
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
skip() {
  echo "SKIPPED: $TEST_NAME: $*"
  exit 77
}
command -v catkin_make >/dev/null || skip "catkin_make not installed"
command -v catkin >/dev/null || skip "catkin (catkin-tools) not installed: scripts/install_deps --test"
command -v roslaunch >/dev/null || skip "roslaunch not installed"
command -v rostest >/dev/null || skip "rostest not installed"
command -v git >/dev/null || skip "git not installed"
git -C "$ROOT" rev-parse --git-dir >/dev/null 2>&1 || skip "$ROOT is not a git checkout"

W=$(mktemp -d /tmp/pmrac_ws.XXXXXX)
FAIL=0
fail() {
  echo "FAIL: $*"
  FAIL=1
}
finish() {
  if [ "$FAIL" = 0 ]; then
    echo "$TEST_NAME: PASSED"
    [ "${PMRAC_WS_KEEP:-0}" = 1 ] || rm -rf "$W"
  else
    echo "$TEST_NAME: FAILED (logs in $W)"
  fi
  exit "$FAIL"
}

# The repository a user clones: this checkout's files (tracked and new, not build outputs),
# committed as they are.
REPO=$W/repository
mkdir -p "$REPO"
(cd "$ROOT" && git ls-files -z --cached --others --exclude-standard |
  tar --null -T - --ignore-failed-read -cf - 2>/dev/null) | tar -xf - -C "$REPO"
(cd "$REPO" && git init -q && git add -A &&
  git -c user.name=test -c user.email=test@localhost commit -qm checkout) ||
  skip "could not make a git repository of the checkout"

# A user's home whose ~/catkin_ws is 40 characters or longer.
USER_HOME=$W/home/a_control_engineer
mkdir -p "$USER_HOME"
WS=$USER_HOME/catkin_ws
[ "${#WS}" -ge 40 ] || fail "the workspace path $WS is shorter than 40 characters"

# The README's catkin blocks, verbatim but for the repository's URL.
readme_block() { # the ```sh block of README.md holding the line that matches $1
  awk -v pat="$1" '/^```sh/ {inb = 1; n = 0; hit = 0; next}
    /^```/ && inb {inb = 0; if (hit) {for (i = 1; i <= n; i++) print b[i]; exit}; next}
    inb {b[++n] = $0; if (index($0, pat)) hit = 1}' "$ROOT/README.md"
}
BLOCK=$(readme_block "catkin_make -D")
TOOLS=$(readme_block "catkin build")
[ -n "$BLOCK" ] || fail "README.md has no \`\`\`sh block with catkin_make -D"
[ -n "$TOOLS" ] || fail "README.md has no \`\`\`sh block with catkin build"
grep -q "<this repository>" <<<"$BLOCK" || fail "README's catkin block clones no '<this repository>'"
[ "$FAIL" = 0 ] || finish
{
  echo "set -e -x"
  while IFS= read -r line; do
    case "$line" in
      rosdep\ install*) echo "# left out (needs the network for rosdep's database): $line" ;;
      *) echo "${line//<this repository>/$REPO}" ;;
    esac
  done <<<"$BLOCK"
  # the named subset of the tests, from the workspace, with the README's environment
  # (PMRAC_ROSTEST_LOCK: a lock file to hold while the rostest's master runs, where engineers
  # share a machine)
  lock=${PMRAC_ROSTEST_LOCK:+flock $PMRAC_ROSTEST_LOCK }
  echo "${lock}catkin_make run_tests_preadaptive_mrac_gtest_test_attention" \
    "run_tests_preadaptive_mrac_rostest_lockstep__mode_rac__shape_nodelet__name_suffix__envelope__test_plant_envelope.test"
  echo 'catkin_test_results build/test_results/preadaptive_mrac'
} >"$W/readme.sh"

# ccache without changing the user's command.
if command -v ccache >/dev/null; then
  export CMAKE_CXX_COMPILER_LAUNCHER=ccache CMAKE_C_COMPILER_LAUNCHER=ccache CCACHE_BASEDIR=$W
fi
# A clean environment, as in a user's new shell (Debian's ROS lives in /usr).
unset ROS_PACKAGE_PATH CMAKE_PREFIX_PATH PYTHONPATH LD_LIBRARY_PATH PKG_CONFIG_PATH \
  PREADAPTIVE_MRAC_CONFIG_DIR ROS_MASTER_URI ROSLISP_PACKAGE_DIRECTORIES
export MAKEFLAGS=-j${PMRAC_WS_JOBS:-2}
t0=$(date +%s)
(cd "$W" && HOME=$USER_HOME ROS_HOME=$W/ros_home bash "$W/readme.sh") >"$W/build.log" 2>&1
rc=$?
echo "README's catkin block in $WS (${#WS} characters), catkin_make with testing on, and" \
  "the named tests: exit $rc in $(($(date +%s) - t0)) s"
if [ "$rc" != 0 ]; then
  grep -E "^\+ |File name too long|Cannot open file|Generate step failed" "$W/build.log" | tail -4 | cut -c1-400 | sed 's/^/    /'
  tail -12 "$W/build.log" | cut -c1-300 | sed 's/^/    /'
  fail "the README's catkin commands"
  finish
fi
grep -q "CATKIN_ENABLE_TESTING.*=ON" "$WS/build/CMakeCache.txt" 2>/dev/null ||
  fail "catkin_make built with testing off"
grep -E "^Summary: " "$W/build.log" | tail -1 | sed 's/^/    /'
# Every rostest target's name fits a file name in any workspace (rostest writes files named so).
long=$(make -C "$WS/build" help 2>/dev/null | sed -n 's/^\.\.\. //p' | awk 'length($0) > 200')
[ -z "$long" ] || fail "target names over 200 characters: $long"

t0=$(date +%s)
(cd "$WS" && catkin_make install) >"$W/install.log" 2>&1
rc=$?
echo "catkin_make install: exit $rc in $(($(date +%s) - t0)) s"
if [ "$rc" != 0 ]; then
  tail -30 "$W/install.log" | sed 's/^/    /'
  fail "catkin_make install"
  finish
fi
# catkin build (catkin-tools), the README's line, in the same workspace.
t0=$(date +%s)
(cd "$WS" && rm -rf build devel && {
  set -e
  while IFS= read -r line; do
    echo "+ $line"
    HOME=$USER_HOME bash -c "$line"
  done <<<"$TOOLS"
  set +u
  # shellcheck disable=SC1091
  source devel/setup.bash
  rosrun preadaptive_mrac preadapt_sim --scenario 1 --mode rac >/dev/null
}) >"$W/catkin_build.log" 2>&1
rc=$?
echo "catkin build and preadapt_sim from its devel space: exit $rc in $(($(date +%s) - t0)) s"
if [ "$rc" != 0 ]; then
  tail -20 "$W/catkin_build.log" | sed 's/^/    /'
  fail "catkin build"
  finish
fi

rm -rf "$WS/src" "$WS/build" "$WS/devel" "$WS/logs" "$WS/.catkin_tools"

# A clean environment: only the install space (Debian's ROS lives in /usr).
unset ROS_PACKAGE_PATH CMAKE_PREFIX_PATH PYTHONPATH LD_LIBRARY_PATH PKG_CONFIG_PATH \
  PREADAPTIVE_MRAC_CONFIG_DIR ROS_MASTER_URI ROSLISP_PACKAGE_DIRECTORIES
set +u
# shellcheck disable=SC1091
source "$WS/install/setup.bash"
set -u
export ROS_HOME=$W/ros_home ROS_LOG_DIR=$W/ros_home/log
PKGLIB=$WS/install/lib/preadaptive_mrac
cd "$W" || exit 1

[ "$(rospack find preadaptive_mrac 2>&1)" = "$WS/install/share/preadaptive_mrac" ] ||
  fail "rospack find preadaptive_mrac: $(rospack find preadaptive_mrac 2>&1)"
for tool in preadapt_sim preadapt_sweep preadapt_family; do
  [ "$(command -v $tool)" = "$WS/install/bin/$tool" ] ||
    fail "$tool not on PATH from the install space (command -v: '$(command -v $tool)')"
done
for exe in preadapt_sim preadapt_sweep preadapt_family plant_sim_node mrac_controller_node \
  bag_recorder_node run_monitor_node pmrac_manager analyze_bag viz_markers live_plot reindex_bags \
  launch_checked; do
  [ -x "$PKGLIB/$exe" ] || fail "$exe not installed in lib/preadaptive_mrac"
done
[ -x "$WS/install/share/preadaptive_mrac/scripts/lib/parent_names" ] ||
  fail "scripts/lib/parent_names (compare.launch's launch-prefix) not installed in share/"
rosrun preadaptive_mrac preadapt_sim --scenario 1 --mode rac >"$W/rosrun.out" 2>&1 ||
  fail "rosrun preadaptive_mrac preadapt_sim: $(tail -3 "$W/rosrun.out")"
for m in rac pa_learn; do
  preadapt_sim --scenario 1 --mode "$m" --seed 1 --json --csv "$W/cli_$m.csv" >"$W/cli_$m.out" 2>&1 ||
    fail "preadapt_sim --scenario 1 --mode $m: $(tail -3 "$W/cli_$m.out")"
done

# A master of our own on a free port; both runs at once against it.
port=$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
export ROS_MASTER_URI=http://127.0.0.1:$port ROS_IP=127.0.0.1 ROS_HOSTNAME=127.0.0.1
roscore -p "$port" >"$W/roscore.log" 2>&1 &
core=$!
for _ in $(seq 100); do rosparam list >/dev/null 2>&1 && break; sleep 0.2; done
declare -A SHAPE=([run_a]=nodelet [run_b]=process [run_c]=nodelet)
declare -A MODE=([run_a]=rac [run_b]=pa_learn [run_c]="rac + pa_learn")
# What a user writes: the package's launch file included in a namespace of their own.
# shellcheck source=test/scripts/lib/include_in_ns.sh
source "$ROOT/test/scripts/lib/include_in_ns.sh"
for ns in run_a run_b; do
  mkdir -p "$W/$ns"
  include_in_ns "$W/$ns.launch" "$ns" scenario.launch scenario=1 mode="${MODE[$ns]}" seed=1 \
    shape="${SHAPE[$ns]}" record=true bag_dir="$W/$ns" latency_report="$W/$ns/plant.json" output=log
done
mkdir -p "$W/run_c"
include_in_ns "$W/run_c.launch" run_c compare.launch scenario=1 pa_mode=pa_learn seed=1 \
  bag_dir="$W/run_c" report_dir="$W/run_c" output=log
declare -A REPORTS=([run_a]=plant.json [run_b]=plant.json [run_c]="rac_plant.json pa_plant.json")
pids=()
for ns in run_a run_b run_c; do
  expect=()
  for r in ${REPORTS[$ns]}; do expect+=(--expect-report "$W/$ns/$r"); done
  "$PKGLIB/launch_checked" --quiet --timeout 240 --log "$W/$ns/launch.log" "${expect[@]}" \
    -- "$W/$ns.launch" 2>"$W/$ns/err" &
  pids+=($!)
done
i=0
for ns in run_a run_b run_c; do
  wait "${pids[$i]}" || fail "$ns (${MODE[$ns]}, ${SHAPE[$ns]} shape) did not complete: $(tail -5 "$W/$ns/err")"
  i=$((i + 1))
done
rosparam get /use_sim_time >/dev/null 2>&1 && fail "/use_sim_time is set on the master"
kill "$core" 2>/dev/null
wait "$core" 2>/dev/null

for ns in run_a run_b; do
  bag=$(ls "$W/$ns"/scenario1_"${MODE[$ns]}"_*.bag 2>/dev/null | head -1)
  if [ -z "$bag" ]; then
    fail "$ns: no bag in $W/$ns"
    continue
  fi
  /usr/bin/python3 "$ROOT/bench/bag_vs_cli.py" "$bag" "$W/cli_${MODE[$ns]}.csv" --ns "/$ns" \
    --tol 0 >"$W/$ns/compare.out" 2>&1 || fail "$ns: bag differs from the CLI: $(cat "$W/$ns/compare.out")"
  echo "$ns (${MODE[$ns]}, ${SHAPE[$ns]}): $(cat "$W/$ns/compare.out")"
  topics=$(/usr/bin/python3 -c 'import rosbag, sys; print(" ".join(sorted(rosbag.Bag(sys.argv[1]).get_type_and_topic_info()[1])))' "$bag")
  case " $topics " in *" /$ns/tf "*) ;; *) fail "$ns: no /$ns/tf in the bag (topics: $topics)" ;; esac
  case " $topics " in *" /tf "*) fail "$ns: the bag holds the global /tf" ;; esac
  if grep -q "adaptation frozen" "$W/$ns/launch.log" "$W"/ros_home/log/*/"$ns"* 2>/dev/null; then
    fail "$ns: the controller went stale (\"adaptation frozen\")"
  fi
done
bag=$(ls "$W"/run_c/scenario1_rac_vs_pa_learn_*.bag 2>/dev/null | grep -v incomplete | head -1)
if [ -z "$bag" ]; then
  fail "run_c: no compare.launch bag in $W/run_c"
else
  for pair in rac pa; do
    m=$([ "$pair" = rac ] && echo rac || echo pa_learn)
    /usr/bin/python3 "$ROOT/bench/bag_vs_cli.py" "$bag" "$W/cli_$m.csv" --ns "/run_c/$pair" \
      --tol 0 >"$W/run_c/compare_$pair.out" 2>&1 ||
      fail "run_c: /run_c/$pair differs from the CLI: $(cat "$W/run_c/compare_$pair.out")"
    echo "run_c (compare.launch, /run_c/$pair): $(cat "$W/run_c/compare_$pair.out")"
  done
  grep -q "adaptation frozen" "$W/run_c/launch.log" "$W"/ros_home/log/*/run_c* 2>/dev/null &&
    fail "run_c: a controller went stale (\"adaptation frozen\")"
fi
# The installed Python package and a script for users, on one of the bags.
bag=$(ls "$W"/run_b/scenario1_pa_learn_*.bag 2>/dev/null | head -1)
if [ -n "$bag" ]; then
  rosrun preadaptive_mrac analyze_bag "$bag" --out "$W/analysis" >"$W/analysis.out" 2>&1 &&
    [ -s "$W/analysis/metrics.json" ] || fail "installed analyze_bag on $bag: $(tail -3 "$W/analysis.out")"
fi

if [ "$FAIL" = 0 ]; then
  echo "ok: installed, source/build/devel removed; tools on PATH and rosrun; three namespaced lockstep runs at once (scenario.launch twice, compare.launch), each bag equal to its CLI runs"
  echo "$TEST_NAME: PASSED"
  [ "${PMRAC_WS_KEEP:-0}" = 1 ] || rm -rf "$W"
else
  echo "$TEST_NAME: FAILED (logs in $W)"
fi
exit "$FAIL"
