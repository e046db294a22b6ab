#!/usr/bin/env bash
# ROS benchmark (not a test): prints a Markdown table for docs/ros.md "Performance".
#   1. lockstep, scenario 3 (140 s at 1 ms = 140 000 round trips), recording on: wall time,
#      round-trip latency, and the bag checked against the batch CLI (bench/bag_vs_cli.py);
#   2. realtime at 1 kHz, scenario 1 (60 s): latency from the state's stamp to the command's
#      arrival at the plant (wall clock) p50/p99/max, and missed (stale) steps.
# Usage: bench/ros_bench.sh [devel/setup.bash]   (default: build_ros/devel/setup.bash)
# Env:   PMRAC_BENCH_PORT (ROS master port, default 11511), PMRAC_BENCH_MODE (default pa_learn),
#        PMRAC_BENCH_SKIP_BAG_CHECK=1 to skip the bag-vs-CLI comparison.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SETUP="${1:-$ROOT/build_ros/devel/setup.bash}"
PORT="${PMRAC_BENCH_PORT:-11511}"
MODE="${PMRAC_BENCH_MODE:-pa_learn}"
PY=/usr/bin/python3   # the interpreter with the ROS modules

set +u  # the ROS setup scripts read unset variables
# shellcheck disable=SC1090
source "$SETUP"
set -u
export ROS_MASTER_URI="http://localhost:$PORT"
WORK="$(mktemp -d "${TMPDIR:-/tmp}/pmrac_ros_bench.XXXXXX")"
export ROS_HOME="$WORK/ros_home"
mkdir -p "$ROS_HOME"
SIM_BIN="$(dirname "$SETUP")/lib/preadaptive_mrac/preadapt_sim"

json() {  # json FILE KEY.PATH
  "$PY" -c 'import json,sys; d=json.load(open(sys.argv[1]));
for k in sys.argv[2].split("."): d=d[k]
print(d)' "$1" "$2"
}

echo "# work dir $WORK; load before: $(cut -d' ' -f1-3 /proc/loadavg)" >&2

# --- 1. lockstep scenario 3 with recording
start=$(date +%s.%N)
# roslaunch exits 0 even when a node died with an error: launch_checked tells (and names the
# refused keys), and checks the plant's report says the run completed.
"$ROOT/scripts/lib/launch_checked" --log "$WORK/lockstep.log" --quiet \
  --expect-report "$WORK/lockstep.json" -- \
  -p "$PORT" preadaptive_mrac scenario.launch scenario:=3 mode:="$MODE" clock:=lockstep \
  record:=true bag_dir:="$WORK/bags" latency_report:="$WORK/lockstep.json" output:=log
end=$(date +%s.%N)
total_lock=$(echo "$end - $start" | bc)
bag=$(ls "$WORK"/bags/*.bag)
bag_check="skipped"
if [ "${PMRAC_BENCH_SKIP_BAG_CHECK:-0}" != "1" ]; then
  "$SIM_BIN" --scenario 3 --mode "$MODE" --dt 0.001 --csv "$WORK/cli3.csv" > /dev/null
  bag_check=$("$PY" "$ROOT/bench/bag_vs_cli.py" "$bag" "$WORK/cli3.csv" || true)
fi
load_lock=$(cut -d' ' -f1 /proc/loadavg)

# --- 2. realtime 1 kHz, scenario 1 (60 s)
"$ROOT/scripts/lib/launch_checked" --log "$WORK/realtime.log" --quiet \
  --expect-report "$WORK/realtime.json" -- \
  -p "$PORT" preadaptive_mrac scenario.launch scenario:=1 mode:="$MODE" clock:=realtime \
  rate:=1000 latency_report:="$WORK/realtime.json" output:=log
load_rt=$(cut -d' ' -f1 /proc/loadavg)

L="$WORK/lockstep.json"
R="$WORK/realtime.json"
cat <<TABLE
| run | steps | wall time [s] | round trip p50 / p99 / max [us] | missed steps | notes |
| --- | --- | --- | --- | --- | --- |
| lockstep, scenario 3, $MODE, recording | $(json "$L" steps) / $(json "$L" total_steps) | $(printf %.1f "$(json "$L" wall_time_s)") (roslaunch total $(printf %.1f "$total_lock")) | $(printf '%.0f / %.0f / %.0f' "$(json "$L" latency_us.p50)" "$(json "$L" latency_us.p99)" "$(json "$L" latency_us.max)") | n/a (lockstep waits) | $(printf '%.0f' "$(echo "$(json "$L" total_steps) / $(json "$L" wall_time_s)" | bc -l)") steps/s; recorder waits $(json "$L" recorder_waits); load $load_lock |
| realtime 1 kHz, scenario 1, $MODE | $(json "$R" steps) / $(json "$R" total_steps) | $(printf %.1f "$(json "$R" wall_time_s)") | $(printf '%.0f / %.0f / %.0f' "$(json "$R" latency_us.p50)" "$(json "$R" latency_us.p99)" "$(json "$R" latency_us.max)") | $(json "$R" stale_steps) stale, $(json "$R" late_ticks) late ticks | commands $(json "$R" commands_received); load $load_rt |

Bag check (lockstep bag vs CLI CSV): $bag_check
TABLE
echo "# logs and reports in $WORK" >&2
