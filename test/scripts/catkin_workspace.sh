#!/usr/bin/env bash
# Issue 23: the package as a ROS user has it. A catkin workspace with the package in src/,
# `catkin_make install`, then the source, build and devel spaces removed; from the install
# space alone:
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
# The catkin build is the cost (ccache is used when present, with CCACHE_BASEDIR so a new
# temporary workspace still hits the cache): PMRAC_WS_JOBS (default 2) parallel jobs.
# PMRAC_WS_KEEP=1 keeps the workspace.
set -uo pipefail
TEST_NAME=catkin_workspace
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
skip() {
  echo "SKIPPED: $TEST_NAME: $*"
  exit 77
}
command -v catkin_make >/dev/null || skip "catkin_make not installed"
command -v roslaunch >/dev/null || skip "roslaunch not installed"
command -v git >/dev/null || skip "git not installed"
git -C "$ROOT" rev-parse --git-dir >/dev/null 2>&1 || skip "$ROOT is not a git checkout"

W=$(mktemp -d /tmp/pmrac_ws.XXXXXX)
WS=$W/ws
FAIL=0
fail() {
  echo "FAIL: $*"
  FAIL=1
}

# The package as it is in this checkout (tracked and new files, not build outputs).
mkdir -p "$WS/src/preadaptive_mrac"
(cd "$ROOT" && git ls-files -z --cached --others --exclude-standard |
  tar --null -T - --ignore-failed-read -cf - 2>/dev/null) | tar -xf - -C "$WS/src/preadaptive_mrac"

launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR=$WS
fi
t0=$(date +%s)
(cd "$WS" && catkin_make install -j"${PMRAC_WS_JOBS:-2}" -DCMAKE_BUILD_TYPE=Release \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=OFF \
  -DPREADAPTIVE_MRAC_BUILD_BENCH=OFF "${launcher[@]}") >"$W/build.log" 2>&1
rc=$?
echo "catkin_make install: exit $rc in $(($(date +%s) - t0)) s"
if [ "$rc" != 0 ]; then
  tail -30 "$W/build.log" | sed 's/^/    /'
  echo "$TEST_NAME: FAILED (logs in $W)"
  exit 1
fi
rm -rf "$WS/src" "$WS/build" "$WS/devel"

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
