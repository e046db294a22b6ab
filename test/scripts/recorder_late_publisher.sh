#!/usr/bin/env bash
# A controller of the user's that starts after the recorder loses no command to the bag, even
# when the recorder is slow to connect to it. plant.launch (process shape, lockstep, recorded)
# waits for a controller; the recorder is stopped (SIGSTOP) before the user's controller
# (scripts/examples/example_lqr_controller) starts, so it cannot connect to the controller's
# command publisher, and resumed (SIGCONT) 2 s later. The plant must not start step 0 until the
# recorder is connected to the commands: the bag holds every state and every command, and the
# plant's wait is on record (its report: no state re-sent). Without that wait the plant ran
# ~2000 steps (~max_recorder_lag) while the recorder was stopped, and their commands were
# missing from the bag.
set -uo pipefail
TEST_NAME=recorder_late_publisher
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$(dirname "$0")/lib/launch_scratch.sh"
MARK="${TEST_NAME}_$$_$(date +%s%N)"
export PMRAC_TEST_MARK=$MARK
marked() { # pids of processes named $1 that carry this test's mark
  local p
  for p in $(pgrep -x "$1"); do
    { tr '\0' '\n' <"/proc/$p/environ"; } 2>/dev/null | grep -qxF "PMRAC_TEST_MARK=$MARK" && echo "$p"
  done
}
roscore -p "$PORT" >"$TMP/roscore.log" 2>&1 &
CORE=$!
RECORDER=""
cleanup() {
  [ -n "$RECORDER" ] && kill -CONT "$RECORDER" 2>/dev/null
  kill -INT $CORE 2>/dev/null
  wait $CORE 2>/dev/null
  rm -rf "$TMP"
}
trap cleanup EXIT
for _ in $(seq 100); do rostopic list >/dev/null 2>&1 && break; sleep 0.1; done

cat >"$TMP/short.yaml" <<'EOF'
scenario:
  name: short
  description: "scenario 1's first 3 s: theta 0.1 (x ones), r 0.1 rad"
  theta:
    - {until: 3.0, scale: 0.1}
  reference:
    - {until: 3.0, r: 0.1}
EOF
roslaunch preadaptive_mrac plant.launch scenario:="$TMP/short.yaml" record:=true \
  bag_dir:="$TMP/bags" accept_from:=/my_controller latency_report:="$TMP/plant.json" \
  >"$TMP/plant.log" 2>&1 &
LAUNCH=$!
# The recorder is up once it publishes its progress; then it is stopped.
for _ in $(seq 300); do
  rostopic list 2>/dev/null | grep -qx /recorder/progress && [ -n "$(marked bag_recorder_no)" ] && break
  sleep 0.1
done
RECORDER=$(marked bag_recorder_no)
check "the recorder runs (one process)" test "$(echo "$RECORDER" | wc -w)" = 1
kill -STOP "$RECORDER"
rosrun preadaptive_mrac example_lqr_controller >"$TMP/my_controller.log" 2>&1 &
CONTROLLER=$!
sleep 2
kill -CONT "$RECORDER"
RECORDER=""
timeout 60 tail --pid=$CONTROLLER -f /dev/null
wait $CONTROLLER
check "your controller exits 0 after the last step" test $? = 0
timeout 60 tail --pid=$LAUNCH -f /dev/null
check "the plant: run completed, 3000 commands taken, no state re-sent" \
  /usr/bin/python3 -c 'import json, sys; r = json.load(open(sys.argv[1])); print("plant:", {k: r[k] for k in ("completed", "commands_received", "resent_states", "recorder_waits")}); sys.exit(not (r["completed"] and r["commands_received"] == 3000 and r["resent_states"] == 0))' "$TMP/plant.json"
BAG=$(ls "$TMP"/bags/short_own_controller_*.bag 2>/dev/null | head -1)
check "the bag is closed" test -n "$BAG"
if [ -n "$BAG" ]; then
  got=$(/usr/bin/python3 -c 'import sys, rosbag; b = rosbag.Bag(sys.argv[1]); print(b.get_message_count("/plant/state"), b.get_message_count("/controller/elevator_cmd"))' "$BAG")
  echo "bag: states and commands: $got"
  check "the bag holds the 3000 states and the 3000 commands" test "$got" = "3000 3000"
fi
[ "$FAIL" = 0 ] || tail -20 "$TMP/plant.log"
[ "$FAIL" = 0 ] && echo "$TEST_NAME: PASSED" || echo "$TEST_NAME: FAILED"
exit "$FAIL"
