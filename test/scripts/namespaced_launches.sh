#!/usr/bin/env bash
# compare.launch and two_machines.launch included in a user's namespace, three runs at
# once on one master, each from a launch file of its own that a user would write
# (<group ns="..."><include .../></group>), lockstep, test/ros/config/short_scenario.yaml (3 s),
# seed 1, recording:
#   run_a: compare.launch, nodelet shape (rac and pa_learn)
#   run_b: compare.launch, process shape (rac and pa)
#   run_c: two_machines.launch part:=all on this machine (pa_learn)
# Each completes (scripts/lib/launch_checked, every plant's report "completed"), each pair's data
# in its run's bag equals its own batch CLI run bit for bit (bench/bag_vs_cli.py --ns --tol 0),
# a compare bag holds its run's tf (/run_a/tf) and no /tf, no controller went stale, no guard
# dropped a message of its loop, and nothing set /use_sim_time. Before: compare.launch loaded
# its pairs into /pmrac_manager (the nodelet shape hung) and had them wait for
# /recorder/progress (the process shape gave up after start_timeout); two_machines.launch set
# the global /use_sim_time and waited for /recorder/progress too.
set -uo pipefail
TEST_NAME=namespaced_launches
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$(dirname "$0")/lib/launch_scratch.sh"
SCEN=$ROOT/test/ros/config/short_scenario.yaml
SIM=$BUILD/devel/lib/preadaptive_mrac/preadapt_sim
LC=$ROOT/scripts/lib/launch_checked
fail() {
  echo "FAIL: $*"
  FAIL=1
}

for m in rac pa pa_learn; do
  "$SIM" --scenario "$SCEN" --mode "$m" --seed 1 --csv "$TMP/cli_$m.csv" >"$TMP/cli_$m.out" 2>&1 ||
    fail "preadapt_sim --mode $m: $(tail -3 "$TMP/cli_$m.out")"
done

roscore -p "$PORT" >"$TMP/roscore.log" 2>&1 &
CORE=$!
trap 'kill "$CORE" 2>/dev/null; wait "$CORE" 2>/dev/null; rm -rf "$TMP"' EXIT
for _ in $(seq 100); do rosparam list >/dev/null 2>&1 && break; sleep 0.2; done

# shellcheck source=test/scripts/lib/include_in_ns.sh
source "$ROOT/test/scripts/lib/include_in_ns.sh"
include() {
  mkdir -p "$TMP/$1"
  include_in_ns "$TMP/$1.launch" "$@"
}
common=(scenario="$SCEN" seed=1 output=log)
include run_a compare.launch "${common[@]}" pa_mode=pa_learn shape=nodelet bag_dir="$TMP/run_a" \
  report_dir="$TMP/run_a"
include run_b compare.launch "${common[@]}" pa_mode=pa shape=process bag_dir="$TMP/run_b" \
  report_dir="$TMP/run_b"
# two_machines.launch: no seed arg, so the CLI runs with the controller YAML's seed below
include run_c two_machines.launch scenario_file="$SCEN" mode=pa_learn output=log record=true \
  bag="$TMP/run_c/two_machines.bag" latency_report="$TMP/run_c/plant.json"
"$SIM" --scenario "$SCEN" --mode pa_learn --csv "$TMP/cli_yaml_seed.csv" >/dev/null 2>&1 ||
  fail "preadapt_sim --mode pa_learn (YAML seed)"

declare -A EXPECT=(
  [run_a]="--expect-report $TMP/run_a/rac_plant.json --expect-report $TMP/run_a/pa_plant.json"
  [run_b]="--expect-report $TMP/run_b/rac_plant.json --expect-report $TMP/run_b/pa_plant.json"
  [run_c]="--expect-report $TMP/run_c/plant.json --expect $TMP/run_c/two_machines.bag")
pids=()
t0=$(date +%s)
for ns in run_a run_b run_c; do
  # shellcheck disable=SC2086
  "$LC" --quiet --timeout 90 --log "$TMP/$ns/launch.log" ${EXPECT[$ns]} -- "$TMP/$ns.launch" \
    2>"$TMP/$ns/err" &
  pids+=($!)
done
i=0
for ns in run_a run_b run_c; do
  wait "${pids[$i]}" || fail "$ns ($(head -c 300 "$TMP/$ns.launch" | grep -o 'launch/[a-z_]*.launch')) did not complete: $(tail -5 "$TMP/$ns/err")"
  i=$((i + 1))
done
echo "three namespaced launches at once: $(($(date +%s) - t0)) s"
rosparam get /use_sim_time >/dev/null 2>&1 && fail "/use_sim_time is set on the master"

# same BAG NS CSV: the pair NS of BAG equals the CLI run CSV bit for bit.
same() {
  if /usr/bin/python3 "$ROOT/bench/bag_vs_cli.py" "$1" "$2" --ns "$3" --tol 0 >"$TMP/cmp.out" 2>&1; then
    echo "ok: $3 equals its CLI run ($(tail -1 "$TMP/cmp.out"))"
  else
    fail "$3 differs from its CLI run: $(tail -3 "$TMP/cmp.out")"
  fi
}
topics() {
  /usr/bin/python3 -c 'import rosbag, sys; print(" ".join(sorted(rosbag.Bag(sys.argv[1]).get_type_and_topic_info()[1])))' "$1"
}
declare -A PA=([run_a]=pa_learn [run_b]=pa)
for ns in run_a run_b; do
  bag=$(ls "$TMP/$ns"/short_scenario_rac_vs_"${PA[$ns]}"_*.bag 2>/dev/null | grep -v incomplete | head -1)
  if [ -z "$bag" ]; then
    fail "$ns: no bag in $TMP/$ns"
    continue
  fi
  same "$bag" "$TMP/cli_rac.csv" "/$ns/rac"
  same "$bag" "$TMP/cli_${PA[$ns]}.csv" "/$ns/pa"
  t=$(topics "$bag")
  case " $t " in *" /$ns/tf "*) ;; *) fail "$ns: no /$ns/tf in the bag (topics: $t)" ;; esac
  case " $t " in *" /tf "*) fail "$ns: the bag holds the global /tf" ;; esac
done
if [ -s "$TMP/run_c/two_machines.bag" ]; then
  same "$TMP/run_c/two_machines.bag" "$TMP/cli_yaml_seed.csv" /run_c
fi
for ns in run_a run_b run_c; do
  logs=("$TMP/$ns/launch.log" "$TMP"/ros_home/log/*/"$ns"*)
  grep -qs "adaptation frozen" "${logs[@]}" && fail "$ns: a controller went stale (\"adaptation frozen\")"
  grep -qs "dropping messages on" "${logs[@]}" && fail "$ns: a guard dropped messages of its loop"
done

[ "$FAIL" = 0 ] && echo "$TEST_NAME: PASSED" || echo "$TEST_NAME: FAILED (logs kept in $TMP.kept)"
[ "$FAIL" = 0 ] || cp -r "$TMP" "$TMP.kept"
exit "$FAIL"
