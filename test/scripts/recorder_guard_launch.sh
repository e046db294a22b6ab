#!/usr/bin/env bash
# The recorder of scenario.launch and compare.launch writes only what the loop's own nodes
# publish: a stray plant (states of step 2^40 on plant/state) and a stray controller (commands
# of that step on controller/elevator_cmd), 500 Hz each, run beside a realtime recorded run.
# The bag holds none of their messages and every state of the run, and the recorder's closing
# line counts the strays' messages it did not write (so they reached it).
set -uo pipefail
TEST_NAME=recorder_guard_launch
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$(dirname "$0")/lib/launch_scratch.sh"
SCEN=$ROOT/test/ros/config/short_scenario.yaml
STRAY=$ROOT/test/ros/stray_publisher.py

# Counts in one bag: "<stray states> <stray commands> <run states>".
count() {
  /usr/bin/python3 - "$1" <<'EOF'
import sys
import rosbag
stray = 1 << 40
s = c = n = 0
with rosbag.Bag(sys.argv[1]) as b:
    for topic, m, _ in b.read_messages():
        if topic.endswith("plant/state"):
            if m.step == stray:
                s += 1
            else:
                n += 1
        elif topic.endswith("controller/elevator_cmd") and m.step == stray:
            c += 1
print(s, c, n)
EOF
}

# CASES="compare nodelet" (comma-separated) runs some of them.
cases=("scenario nodelet" "scenario process" "compare nodelet")
[ -n "${CASES:-}" ] && IFS=, read -ra cases <<<"$CASES"
# A realtime plant that stalled for seconds under load (docs/notebook.md, "A realtime plant that
# stalled for 7 s under load"): the controller then says the plant has gone and ends the launch,
# so the bag lacks the run's last states. Likewise a plant nodelet that its manager unloaded
# mid-run under load (nothing here stops its loader; its bond timed out). That is not what this
# test checks: such a case is said, with the plant's and the controller's lines, and run once
# more. A second one fails.
stalled() {  # stalled LOG: the controller ended the run on a plant silent for 2 s (nothing
  # here stops the plant, so a silent plant is a stalled one), or the plant was unloaded
  grep -aqE "the plant has gone|unloaded before its run ended" "$1"
}
declare -A retried=()
i=0
while [ "$i" -lt "${#cases[@]}" ]; do
  CASE=${cases[$i]}
  i=$((i + 1))
  read -r L SHAPE <<<"$CASE"
  NS=""
  [ "$L" = compare ] && NS=rac
  # A master of the test's own, the strays on it and seen by it, then the launch (which uses
  # that master): the strays publish before the run starts.
  start_master
  ROS_NAMESPACE=$NS /usr/bin/python3 "$STRAY" __name:=stray_plant _kind:=state _step_log2:=40 \
    _rate:=500 >"$TMP/stray_plant.log" 2>&1 &
  P1=$!
  ROS_NAMESPACE=$NS /usr/bin/python3 "$STRAY" __name:=stray_commander _kind:=command \
    _step_log2:=40 _u:=0.0123456 _rate:=500 >"$TMP/stray_cmd.log" 2>&1 &
  P2=$!
  for _ in $(seq 50); do
    [ "$(timeout 5 rostopic info "${NS:+/$NS}/plant/state" 2>/dev/null | grep -c stray_plant)" = 1 ] &&
      [ "$(timeout 5 rostopic info "${NS:+/$NS}/controller/elevator_cmd" 2>/dev/null |
        grep -c stray_commander)" = 1 ] && break
    sleep 0.2
  done
  LOG=$TMP/$L-$SHAPE.log
  BAGS=$TMP/bags-$L-$SHAPE
  RC=0
  timeout 120 roslaunch -p "$PORT" preadaptive_mrac "$L.launch" scenario:="$SCEN" shape:="$SHAPE" \
    clock:=realtime record:=true bag_dir:="$BAGS" >"$LOG" 2>&1 || RC=$?
  kill "$P1" "$P2" "$PM" 2>/dev/null
  wait "$P1" "$P2" "$PM" 2>/dev/null
  BAG=$(find "$BAGS" -name '*.bag' | head -1)
  if [ "$RC" != 0 ] || [ -z "$BAG" ]; then
    echo "FAIL: $L.launch shape:=$SHAPE: exit $RC, bag '${BAG}'"
    grep -E "WARN|ERROR|finished|stray|waiting|run_monitor|closed" "$LOG" | head -30
    FAIL=1
    continue
  fi
  read -r S C N < <(count "$BAG")
  echo "$L.launch shape:=$SHAPE: stray states $S, stray commands $C, run states $N"
  # compare.launch records two runs; scenario.launch one (3000 steps).
  want=3000
  [ "$L" = compare ] && want=6000
  if [ "$N" != "$want" ] && [ -z "${retried[$CASE]:-}" ] && stalled "$LOG"; then
    echo "NOTE: $L $SHAPE: the plant stalled or was unloaded, and the run ended early; once more:"
    grep -aE "scenario complete|has gone|unloaded before" "$LOG" | sed 's/\x1b\[[0-9;]*m//g' | cut -c1-300 |
      sed 's/^/    /'
    retried[$CASE]=1
    cases+=("$CASE")
    rm -rf "$BAGS"
    continue
  fi
  check "$L $SHAPE: no stray message in the bag" [ "$S$C" = 00 ]
  check "$L $SHAPE: every state of the run in the bag ($N of $want)" [ "$N" = "$want" ]
  # Why not: the plant's closing line (its wall time, late ticks) and any node that ended early.
  [ "$N" = "$want" ] || grep -aE "scenario complete|has gone|has died|exit code" "$LOG" |
    sed 's/\x1b\[[0-9;]*m//g' | cut -c1-300 | sed 's/^/    /'
  # The strays reached the recorder, which counted what it did not write.
  check "$L $SHAPE: the recorder names the strays it did not write" \
    grep -q "not written, from publishers not in ~accept_from: .*stray_" "$LOG"
done
pgrep -f "$STRAY" >/dev/null && { echo "FAIL: a stray publisher was left"; FAIL=1; }
[ "$FAIL" = 0 ] && echo "recorder_guard_launch: PASSED" || echo "recorder_guard_launch: FAILED"
exit "$FAIL"
