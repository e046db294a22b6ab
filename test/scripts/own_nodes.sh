#!/usr/bin/env bash
# The nodes used apart (docs/tutorials/own_controller.md, docs/tutorials/own_plant.md), each
# against a node of the user's, as the tutorials run them: a master of its own, the launch file
# in one shell, the user's node in another.
# 1. Your controller against the plant node: plant.launch (lockstep, scenario 1, recorded,
#    taking commands only from /my_controller) and scripts/examples/example_lqr_controller.
#    The run completes, every step answered once and nothing re-sent, the LQR holds alpha at r,
#    and the bag holds every state and command.
# 2. The controller against your plant: controller.launch and scripts/examples/example_plant,
#    once with rac and once with pa_robust (recorded). Both plants finish every step, pa_robust's
#    peak error after the switch of theta is below rac's, the bag is analysed, and the
#    controller's launch ends cleanly on Ctrl-C, leaving no process behind.
set -uo pipefail
TEST_NAME=own_nodes
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$(dirname "$0")/lib/launch_scratch.sh"

roscore -p "$PORT" >"$TMP/roscore.log" 2>&1 &
CORE=$!
trap 'kill -INT $CORE 2>/dev/null; wait $CORE 2>/dev/null; rm -rf "$TMP"' EXIT
for _ in $(seq 100); do rostopic list >/dev/null 2>&1 && break; sleep 0.1; done

count() { # count BAG TOPIC: messages on TOPIC in BAG
  /usr/bin/python3 -c 'import sys, rosbag; b = rosbag.Bag(sys.argv[1]); print(b.get_message_count(sys.argv[2]))' "$1" "$2"
}

# 1. Your controller against the plant node.
roslaunch preadaptive_mrac plant.launch scenario:=1 record:=true bag_dir:="$TMP/bags" \
  accept_from:=/my_controller latency_report:="$TMP/plant.json" >"$TMP/plant.log" 2>&1 &
LAUNCH=$!
timeout 120 rosrun preadaptive_mrac example_lqr_controller >"$TMP/my_controller.log" 2>&1
rc=$?
timeout 60 tail --pid=$LAUNCH -f /dev/null
check "your controller: it exits 0 after the plant's last step" test "$rc" = 0
check "your controller: 60000 steps answered" grep -q "answered 60000 steps" "$TMP/my_controller.log"
check "your controller: the LQR holds alpha at r (last |alpha - r| < 1e-3 rad, |alpha| < 0.5 rad)" \
  /usr/bin/python3 -c 'import re, sys; m = re.search(r"largest \|alpha\| ([0-9.]+) rad, last \|alpha - r\| ([0-9.]+)", open(sys.argv[1]).read()); sys.exit(not (m and float(m.group(1)) < 0.5 and float(m.group(2)) < 1e-3))' "$TMP/my_controller.log"
check "the plant: run completed, 60000 commands taken from /my_controller, none ignored or re-sent" \
  /usr/bin/python3 -c 'import json, sys; r = json.load(open(sys.argv[1])); sys.exit(not (r["completed"] and r["commands_received"] == 60000 and r["commands_ignored"] == 0 and r["resent_states"] == 0))' "$TMP/plant.json"
BAG=$(ls "$TMP"/bags/scenario1_own_controller_*.bag 2>/dev/null | head -1)
check "the bag scenario1_own_controller_*.bag is closed" test -n "$BAG"
if [ -n "$BAG" ]; then
  check "the bag holds 60000 states and 60000 of your commands" \
    test "$(count "$BAG" /plant/state) $(count "$BAG" /controller/elevator_cmd)" = "60000 60000"
fi
[ "$FAIL" = 0 ] || { tail -20 "$TMP/plant.log"; tail -5 "$TMP/my_controller.log"; }

# 2. The controller against your plant, rac then pa_robust.
peak_after_switch() { sed -n 's/.*from *5.00 s.*peak |alpha - r| \([0-9.]*\) rad/\1/p' "$1"; }
for mode in rac pa_robust; do
  roslaunch preadaptive_mrac controller.launch mode:=$mode record:=true bag_dir:="$TMP/bags" \
    >"$TMP/controller_$mode.log" 2>&1 &
  LAUNCH=$!
  timeout 120 rosrun preadaptive_mrac example_plant >"$TMP/my_plant_$mode.log" 2>&1
  check "your plant with $mode: it exits 0 after every step" test "$?" = 0
  kill -INT $LAUNCH
  timeout 20 tail --pid=$LAUNCH -f /dev/null
  check "controller.launch ($mode) ends on Ctrl-C within 20 s" bash -c "! kill -0 $LAUNCH 2>/dev/null"
  wait $LAUNCH 2>/dev/null
done
RAC=$(peak_after_switch "$TMP/my_plant_rac.log")
ROB=$(peak_after_switch "$TMP/my_plant_pa_robust.log")
echo "peak |alpha - r| after the switch to theta = 2: rac $RAC rad, pa_robust $ROB rad"
check "pa_robust's peak after the switch is below rac's" \
  /usr/bin/python3 -c 'import sys; sys.exit(not (0 < float(sys.argv[1]) < float(sys.argv[2])))' "${ROB:-0}" "${RAC:-0}"
BAG=$(ls "$TMP"/bags/own_plant_pa_robust_*.bag 2>/dev/null | head -1)
check "the bag own_plant_pa_robust_*.bag is closed" test -n "$BAG"
if [ -n "$BAG" ]; then
  check "the bag holds the 20000 states of your plant, each once, and 20000 commands" \
    test "$(count "$BAG" /plant/state) $(count "$BAG" /controller/elevator_cmd)" = "20000 20000"
  check "analyze_bag reads it" bash -c 'rosrun preadaptive_mrac analyze_bag "$1" --no-figures --out "$2" >"$3" 2>&1' \
    _ "$BAG" "$TMP/analysis" "$TMP/analysis.log"
fi
check "no node is left on the master but rosout" test "$(rosnode list 2>&1)" = /rosout
[ "$FAIL" = 0 ] || { tail -20 "$TMP/controller_pa_robust.log"; tail -5 "$TMP/my_plant_pa_robust.log"; tail -5 "$TMP/analysis.log" 2>/dev/null; }
[ "$FAIL" = 0 ] && echo "$TEST_NAME: PASSED" || echo "$TEST_NAME: FAILED"
exit "$FAIL"
