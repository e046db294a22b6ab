#!/usr/bin/env bash
# ROS benchmark (not a test): both shapes (nodelet: one pmrac_manager process; process: one
# process per node) in one run, interleaved, so that their ratio is measured under the same
# load. Prints a Markdown table of medians for docs/reference/ros.md and docs/performance.md:
#   1. lockstep, scenario 3 (140 s at 1 ms = 140 000 round trips), $MODE, recording on: the
#      plant's wall time from step 0 to the last step, roslaunch's total, round-trip latency;
#      the first nodelet bag is checked against the batch CLI (bench/bag_vs_cli.py); then the
#      same run without recording (the loop alone);
#   2. compare.launch, scenario 1 (two loops, rac and $MODE, recording on): roslaunch's total
#      and the slower plant's wall time;
#   3. realtime at 1 kHz, scenario 1 (60 s): latency from the state's stamp to the command's
#      arrival at the plant p50/p99/max, stale steps, late ticks; before them, the machine's
#      floor for such a loop (wakeup_floor, 20 s: timer wake-up lateness of one thread doing
#      nothing, and CPU taken from a spinning thread, at the same scheduling);
#   4. optionally the realtime runs again under a deliberate load (a busy process per CPU).
# The 1-minute load average is recorded before each run; the table gives its range.
# Usage: bench/ros_bench.sh [devel/setup.bash]   (default: build/devel/setup.bash)
# Env:   PMRAC_BENCH_PORT (ROS master port, default 11511), PMRAC_BENCH_MODE (pa_learn),
#        PMRAC_BENCH_REPS (lockstep and compare runs per shape, 3), PMRAC_BENCH_RT_REPS
#        (realtime runs per shape, 1), PMRAC_BENCH_RT_PRIORITY (rt_priority of the realtime
#        runs, 0 = normal scheduling), PMRAC_BENCH_SHAPES ("nodelet process"),
#        PMRAC_BENCH_SKIP_BAG_CHECK=1 to skip the bag-vs-CLI comparison, PMRAC_BENCH_FLOOR_S
#        (seconds of each wakeup_floor measurement, 20), PMRAC_BENCH_RT_LOADED_REPS (realtime
#        runs per shape under a deliberate load, one busy process per CPU; 0).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SETUP="${1:-$ROOT/build/devel/setup.bash}"
PORT="${PMRAC_BENCH_PORT:-11511}"
MODE="${PMRAC_BENCH_MODE:-pa_learn}"
REPS="${PMRAC_BENCH_REPS:-3}"
RT_REPS="${PMRAC_BENCH_RT_REPS:-1}"
RT_PRIO="${PMRAC_BENCH_RT_PRIORITY:-0}"
RT_LOADED_REPS="${PMRAC_BENCH_RT_LOADED_REPS:-0}"
SHAPES="${PMRAC_BENCH_SHAPES:-nodelet process}"
PY=/usr/bin/python3 # the interpreter with the ROS modules

set +u # the ROS setup scripts read unset variables
# shellcheck disable=SC1090
source "$SETUP"
set -u
export ROS_MASTER_URI="http://localhost:$PORT"
WORK="$(mktemp -d "${TMPDIR:-/tmp}/pmrac_ros_bench.XXXXXX")"
export ROS_HOME="$WORK/ros_home"
mkdir -p "$ROS_HOME"
SIM_BIN="$(dirname "$SETUP")/lib/preadaptive_mrac/preadapt_sim"
RESULTS="$WORK/results.tsv" # kind shape rep load roslaunch_s report...
: >"$RESULTS"
load1() { cut -d' ' -f1 /proc/loadavg; }
now() { date +%s.%N; }

echo "# work dir $WORK; load before: $(cut -d' ' -f1-3 /proc/loadavg)" >&2
# roslaunch exits 0 even when a node died with an error: launch_checked tells (and names the
# refused keys), and checks each plant's report says the run completed.
checked() { "$ROOT/scripts/lib/launch_checked" --quiet "$@"; }
# timed KIND SHAPE REP REPORTS -- LAUNCH_CHECKED_ARGS...: one run, a line in $RESULTS (the load
# before it, roslaunch's total wall time, the plant reports, comma-separated).
timed() {
  local kind=$1 shape=$2 rep=$3 reports=$4 l t0
  shift 5
  l=$(load1)
  t0=$(now)
  checked "$@"
  printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$kind" "$shape" "$rep" "$l" "$(echo "$(now) - $t0" | bc)" \
    "$reports" >>"$RESULTS"
}

for rep in $(seq 1 "$REPS"); do
  for shape in $SHAPES; do
    d="$WORK/$shape.$rep"
    mkdir -p "$d"
    # --- 1. lockstep scenario 3 with recording
    timed lockstep "$shape" "$rep" "$d/lockstep.json" -- --log "$d/lockstep.log" \
      --expect-report "$d/lockstep.json" -- -p "$PORT" preadaptive_mrac scenario.launch \
      scenario:=3 mode:="$MODE" clock:=lockstep shape:="$shape" record:=true \
      bag_dir:="$d/bags" latency_report:="$d/lockstep.json" output:=log
    # Keep the first nodelet bag for the check against the CLI (about 90 MB each).
    [ "$shape.$rep" = nodelet.1 ] || rm -rf "$d/bags"
    # --- 1b. the same without recording: the loop alone
    timed lockstep_norec "$shape" "$rep" "$d/lockstep_norec.json" -- \
      --log "$d/lockstep_norec.log" --expect-report "$d/lockstep_norec.json" -- -p "$PORT" \
      preadaptive_mrac scenario.launch scenario:=3 mode:="$MODE" clock:=lockstep \
      shape:="$shape" record:=false latency_report:="$d/lockstep_norec.json" output:=log
    # --- 2. compare.launch scenario 1 (two loops, recording on)
    timed compare "$shape" "$rep" "$d/rac_plant.json,$d/pa_plant.json" -- \
      --log "$d/compare.log" --expect-report "$d/rac_plant.json" \
      --expect-report "$d/pa_plant.json" -- -p "$PORT" preadaptive_mrac compare.launch \
      scenario:=1 pa_mode:="$MODE" shape:="$shape" bag_dir:="$d/bags_compare" report_dir:="$d" \
      output:=log
    rm -rf "$d/bags_compare"
    echo "# rep $rep $shape: lockstep and compare done (load $(load1))" >&2
  done
done
FLOOR_JSON=""
if [ "$RT_REPS" -gt 0 ]; then
  FLOOR_BIN="$(dirname "$SETUP")/lib/preadaptive_mrac/wakeup_floor"
  if [ -x "$FLOOR_BIN" ]; then
    FLOOR_JSON="$WORK/wakeup_floor.json"
    "$FLOOR_BIN" --seconds "${PMRAC_BENCH_FLOOR_S:-20}" --priority "$RT_PRIO" --json >"$FLOOR_JSON"
    echo "# wakeup_floor done (load $(load1))" >&2
  fi
fi
# realtime KIND REP SHAPE: one realtime 1 kHz scenario 1 run.
realtime() {
  local kind=$1 rep=$2 shape=$3 d="$WORK/$3.$1$2"
  mkdir -p "$d"
  timed "$kind" "$shape" "$rep" "$d/realtime.json" -- --log "$d/realtime.log" \
    --expect-report "$d/realtime.json" -- -p "$PORT" preadaptive_mrac scenario.launch \
    scenario:=1 mode:="$MODE" clock:=realtime shape:="$shape" rate:=1000 \
    rt_priority:="$RT_PRIO" latency_report:="$d/realtime.json" output:=log
  echo "# $kind rep $rep $shape done (load $(load1))" >&2
}
for rep in $(seq 1 "$RT_REPS"); do
  for shape in $SHAPES; do
    # --- 3. realtime 1 kHz, scenario 1
    realtime realtime "$rep" "$shape"
  done
done
# --- 4. the same realtime runs under a deliberate load: one busy process (normal scheduling)
# per CPU for the length of the runs.
if [ "$RT_LOADED_REPS" -gt 0 ]; then
  BUSY=()
  for _ in $(seq 1 "$(nproc)"); do
    (while :; do :; done) &
    BUSY+=($!)
  done
  trap 'kill "${BUSY[@]}" 2>/dev/null || true' EXIT
  for rep in $(seq 1 "$RT_LOADED_REPS"); do
    for shape in $SHAPES; do
      realtime realtime_loaded "$rep" "$shape"
    done
  done
  kill "${BUSY[@]}" 2>/dev/null || true
  trap - EXIT
fi

bag_check="skipped"
first_bag=$(ls "$WORK"/nodelet.1/bags/*.bag 2>/dev/null | head -1 || true)
if [ "${PMRAC_BENCH_SKIP_BAG_CHECK:-0}" != "1" ] && [ -n "$first_bag" ]; then
  "$SIM_BIN" --scenario 3 --mode "$MODE" --dt 0.001 --csv "$WORK/cli3.csv" >/dev/null
  bag_check=$("$PY" "$ROOT/bench/bag_vs_cli.py" "$first_bag" "$WORK/cli3.csv" || true)
fi

"$PY" - "$RESULTS" "$MODE" "$REPS" "$RT_REPS" "$RT_PRIO" "$FLOOR_JSON" <<'PY'
import json, statistics, sys
path, mode, reps, rt_reps, rt_prio, floor_path = sys.argv[1:]
rows = [l.rstrip("\n").split("\t") for l in open(path) if l.strip()]
def med(xs):
    return statistics.median(xs) if xs else float("nan")
def runs(kind, shape):
    return [r for r in rows if r[0] == kind and r[1] == shape]
shapes = [s for s in dict.fromkeys(r[1] for r in rows)]
def loads(rs):
    ls = [float(r[3]) for r in rs]
    return "%.2f-%.2f" % (min(ls), max(ls)) if ls else "n/a"
out = {}
for shape in shapes:
    lk = runs("lockstep", shape)
    rep = [json.load(open(r[5])) for r in lk]
    nr = runs("lockstep_norec", shape)
    nrep = [json.load(open(r[5])) for r in nr]
    cm = runs("compare", shape)
    cmp_wall = [max(json.load(open(f))["wall_time_s"] for f in r[5].split(",")) for r in cm]
    rt = [json.load(open(r[5])) for r in runs("realtime", shape)]
    out[shape] = dict(
        lock_wall=med([j["wall_time_s"] for j in rep]), lock_total=med([float(r[4]) for r in lk]),
        lock_p50=med([j["latency_us"]["p50"] for j in rep]),
        lock_p99=med([j["latency_us"]["p99"] for j in rep]),
        lock_steps="%d / %d" % (rep[0]["steps"], rep[0]["total_steps"]) if rep else "n/a",
        lock_waits=med([j["recorder_waits"] for j in rep]), lock_load=loads(lk),
        nr_wall=med([j["wall_time_s"] for j in nrep]), nr_total=med([float(r[4]) for r in nr]),
        nr_p50=med([j["latency_us"]["p50"] for j in nrep]),
        nr_p99=med([j["latency_us"]["p99"] for j in nrep]), nr_load=loads(nr),
        cmp_wall=med(cmp_wall), cmp_total=med([float(r[4]) for r in cm]), cmp_load=loads(cm),
        rt_p50=med([j["latency_us"]["p50"] for j in rt]), rt_p99=med([j["latency_us"]["p99"] for j in rt]),
        rt_max=med([j["latency_us"]["max"] for j in rt]), rt_stale=med([j["stale_steps"] for j in rt]),
        rt_late=med([j["late_ticks"] for j in rt]), rt_wall=med([j["wall_time_s"] for j in rt]),
        rt_sched=rt[0].get("scheduling", "?") if rt else "n/a", rt_load=loads(runs("realtime", shape)),
    )
    rl = [json.load(open(r[5])) for r in runs("realtime_loaded", shape)]
    out[shape].update(
        rl_n=len(rl), rl_p50=med([j["latency_us"]["p50"] for j in rl]),
        rl_p99=med([j["latency_us"]["p99"] for j in rl]), rl_max=med([j["latency_us"]["max"] for j in rl]),
        rl_stale=med([j["stale_steps"] for j in rl]), rl_late=med([j["late_ticks"] for j in rl]),
        rl_wall=med([j["wall_time_s"] for j in rl]), rl_sched=rl[0].get("scheduling", "?") if rl else "n/a",
        rl_load=loads(runs("realtime_loaded", shape)))
print("| run | shape | wall time [s] (median) | roslaunch total [s] | round trip p50 / p99 / max [us] | stale steps / late ticks | load (1 min) |")
print("| --- | --- | --- | --- | --- | --- | --- |")
for s in shapes:
    o = out[s]
    print("| lockstep, scenario 3, %s, recording (%s runs) | %s | %.2f | %.1f | %.0f / %.0f / - | n/a (recorder waits %.0f) | %s |"
          % (mode, reps, s, o["lock_wall"], o["lock_total"], o["lock_p50"], o["lock_p99"], o["lock_waits"], o["lock_load"]))
for s in shapes:
    o = out[s]
    print("| lockstep, scenario 3, %s, no recording (%s runs) | %s | %.2f | %.1f | %.0f / %.0f / - | - | %s |"
          % (mode, reps, s, o["nr_wall"], o["nr_total"], o["nr_p50"], o["nr_p99"], o["nr_load"]))
for s in shapes:
    o = out[s]
    print("| compare.launch, scenario 1, rac + %s, recording (%s runs) | %s | %.2f (slower plant) | %.1f | - | - | %s |"
          % (mode, reps, s, o["cmp_wall"], o["cmp_total"], o["cmp_load"]))
for s in shapes if int(rt_reps) > 0 else []:
    o = out[s]
    print("| realtime 1 kHz, scenario 1, %s (%s runs, %s) | %s | %.3f | - | %.0f / %.0f / %.0f | %.0f / %.0f | %s |"
          % (mode, rt_reps, o["rt_sched"], s, o["rt_wall"], o["rt_p50"], o["rt_p99"], o["rt_max"], o["rt_stale"], o["rt_late"], o["rt_load"]))
for s in shapes:
    o = out[s]
    if o["rl_n"]:
        print("| realtime 1 kHz, scenario 1, %s, under load: a busy process per CPU (%d runs, %s) | %s | %.3f | - | %.0f / %.0f / %.0f | %.0f / %.0f | %s |"
              % (mode, o["rl_n"], o["rl_sched"], s, o["rl_wall"], o["rl_p50"], o["rl_p99"], o["rl_max"], o["rl_stale"], o["rl_late"], o["rl_load"]))
if floor_path:
    f = json.load(open(floor_path))
    t, g = f["timer"], f["spin_gaps_over_20us"]
    print("| machine floor (wakeup_floor, one thread, no ROS, %s): timer wake-up | - | %.0f | - | late %.0f / %.0f / %.0f | %d of %d ticks > 1 ms | - |"
          % (f["scheduling"], t["count"] * f["period_us"] * 1e-6, t["p50_us"], t["p99_us"], t["max_us"], t["over_1ms"], t["count"]))
    print("| machine floor: CPU taken from a spinning thread | - | %.0f | - | longest gap %.0f | %d gaps > 1 ms, %d > 200 us | - |"
          % (f["spin_seconds"], g["max_us"], g["over_1ms"], g["over_200us"]))
if "nodelet" in out and "process" in out:
    n, p = out["nodelet"], out["process"]
    print()
    print("Ratios process / nodelet (same run): lockstep wall %.2fx, lockstep roslaunch total %.2fx, "
          "compare wall %.2fx, compare roslaunch total %.2fx, realtime p99 %.2fx."
          % (p["lock_wall"] / n["lock_wall"], p["lock_total"] / n["lock_total"],
             p["cmp_wall"] / n["cmp_wall"], p["cmp_total"] / n["cmp_total"], p["rt_p99"] / n["rt_p99"]))
PY
echo
echo "Bag check (first nodelet lockstep bag vs CLI CSV): $bag_check"
echo "# logs and reports in $WORK" >&2
