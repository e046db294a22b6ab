#!/usr/bin/env bash
# two lockstep runs in one launch file (launch/side_by_side.launch: two
# scenario.launch includes in <group ns="run_a"> and <group ns="run_b"> with ends_launch:=false,
# and a required run monitor), recording, seed 1: run_a rac on test/ros/config/short_scenario.yaml
# (3 s), run_b pa_learn on scenario 1 (60 s), so run_a ends well before run_b (the issue's case);
# once in the nodelet shape, once in the process shape.
# Each run goes to its end (launch_checked exits 0, both plants' reports "completed"), each
# writes one complete bag (no ...incomplete.bag), and each bag equals its own batch CLI run
# bit for bit (bench/bag_vs_cli.py --ns /run_x --tol 0). Before: the plant of scenario.launch
# was required with no way out, so the first run to finish ended the launch and the other's
# bag was closed as ...incomplete.bag.
set -uo pipefail
TEST_NAME=two_runs_one_launch
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$(dirname "$0")/lib/launch_scratch.sh"
# the scenario argument of each run, and the name its bag starts with
declare -A SCEN=([run_a]=$ROOT/test/ros/config/short_scenario.yaml [run_b]=1)
declare -A TAG=([run_a]=short_scenario [run_b]=scenario1)
SIM=$BUILD/devel/lib/preadaptive_mrac/preadapt_sim
fail() {
  echo "FAIL: $*"
  FAIL=1
}
declare -A MODE=([run_a]=rac [run_b]=pa_learn)
for ns in run_a run_b; do
  "$SIM" --scenario "${SCEN[$ns]}" --mode "${MODE[$ns]}" --seed 1 \
    --csv "$TMP/cli_$ns.csv" >"$TMP/cli_$ns.out" 2>&1 || fail "preadapt_sim $ns: $(tail -3 "$TMP/cli_$ns.out")"
done

for shape in nodelet process; do
  D=$TMP/$shape
  mkdir -p "$D"
  t0=$(date +%s)
  if ! "$ROOT/scripts/lib/launch_checked" --quiet --timeout 120 --log "$D/launch.log" \
    --expect-report "$D/run_a_plant.json" --expect-report "$D/run_b_plant.json" -- \
    -p "$PORT" preadaptive_mrac side_by_side.launch scenario:="${SCEN[run_a]}" mode_a:=rac scenario_b:="${SCEN[run_b]}" \
    mode_b:=pa_learn \
    seed:=1 shape:="$shape" bag_dir:="$D" report_dir:="$D" output:=log 2>"$D/err"; then
    fail "$shape: the launch did not complete: $(tail -5 "$D/err")"
  fi
  echo "$shape: two runs in one launch file: $(($(date +%s) - t0)) s"
  for ns in run_a run_b; do
    m=${MODE[$ns]}
    ls "$D/$ns"/*.incomplete.bag >/dev/null 2>&1 && fail "$shape $ns: an incomplete bag: $(ls "$D/$ns")"
    bags=("$D/$ns/${TAG[$ns]}_${m}"_*.bag)
    if [ ! -f "${bags[0]}" ] || [ ${#bags[@]} -ne 1 ]; then
      fail "$shape $ns: not one bag in $D/$ns ($(ls "$D/$ns" 2>/dev/null | paste -sd' '))"
      continue
    fi
    if /usr/bin/python3 "$ROOT/bench/bag_vs_cli.py" "${bags[0]}" "$TMP/cli_$ns.csv" --ns "/$ns" --tol 0 \
      >"$D/$ns.cmp" 2>&1; then
      echo "ok: $shape $ns ($m) equals its CLI run ($(tail -1 "$D/$ns.cmp"))"
    else
      fail "$shape $ns ($m) differs from its CLI run: $(tail -3 "$D/$ns.cmp")"
    fi
  done
done

[ "$FAIL" = 0 ] && echo "$TEST_NAME: PASSED" || echo "$TEST_NAME: FAILED (logs kept in $TMP.kept)"
[ "$FAIL" = 0 ] || cp -r "$TMP" "$TMP.kept"
exit "$FAIL"
