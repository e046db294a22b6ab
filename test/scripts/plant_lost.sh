#!/usr/bin/env bash
# The controller stops when its plant is gone (~plant_lost_samples, realtime): the controller
# alone (launch/controller.launch clock:=realtime) flies a plant of a second launch
# (launch/plant.launch); the plant is SIGKILLed mid-run. Checks: the controller logs one ERROR
# naming the cause, publishes nothing more once ~plant_lost_samples sample times (2000 x 1 ms)
# have passed, and its launch ends within seconds. Before: it sent stale commands without end
# and its launch never ended.
set -uo pipefail
TEST_NAME=plant_lost
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$(dirname "$0")/lib/launch_scratch.sh"
command -v rosrun >/dev/null || skip "rosrun not installed"

roslaunch preadaptive_mrac controller.launch clock:=realtime mode:=rac start_timeout:=60 \
  >"$TMP/controller.log" 2>&1 &
CTL=$!
for _ in $(seq 300); do rostopic list >/dev/null 2>&1 && break; sleep 0.1; done
# A subscriber of the commands: the wall time of each, relative to its start.
/usr/bin/python3 - "$TMP/cmds.txt" >"$TMP/listener.log" 2>&1 <<'PY' &
import sys, time, rospy
from preadaptive_mrac.msg import ElevatorCommand
out = open(sys.argv[1], "w", buffering=1)
rospy.init_node("plant_lost_listener", anonymous=True)
rospy.Subscriber("controller/elevator_cmd", ElevatorCommand,
                 lambda m: out.write("%.4f\n" % time.time()), queue_size=10000)
rospy.spin()
PY
LISTENER=$!
roslaunch preadaptive_mrac plant.launch clock:=realtime scenario:=1 start_timeout:=60 \
  >"$TMP/plant.log" 2>&1 &
PLANT_LAUNCH=$!
cleanup() {
  for p in $PLANT_LAUNCH $CTL $LISTENER; do kill -INT "$p" 2>/dev/null; done
  sleep 1
  for p in $PLANT_LAUNCH $CTL $LISTENER; do kill -9 "$p" 2>/dev/null; done
  rm -rf "$TMP"
}
trap cleanup EXIT

# The plant node of the second launch (a child of that roslaunch).
plant_pid() { ps -eo pid,ppid,args | awk -v p="$PLANT_LAUNCH" '$2 == p && /plant_sim_node/ {print $1}'; }
for _ in $(seq 600); do
  [ -s "$TMP/cmds.txt" ] && [ "$(wc -l <"$TMP/cmds.txt")" -gt 2000 ] && [ -n "$(plant_pid)" ] && break
  sleep 0.1
done
PID=$(plant_pid)
[ -n "$PID" ] || { echo "FAIL: no plant_sim_node under the plant's launch"; tail -20 "$TMP/plant.log"; exit 1; }
[ "$(wc -l <"$TMP/cmds.txt")" -gt 2000 ] || { echo "FAIL: the loop never ran"; tail -20 "$TMP/controller.log"; exit 1; }
T_KILL=$(date +%s.%N)
kill -9 "$PID"

ENDED=0
for _ in $(seq 150); do
  kill -0 "$CTL" 2>/dev/null || { ENDED=1; break; }
  sleep 0.1
done
T_END=$(date +%s.%N)
sleep 0.5
check "the controller's launch ended within 15 s of the kill ($(echo "$T_END - $T_KILL" | bc) s)" \
  test "$ENDED" = 1
check "the controller said why, once" \
  test "$(grep -c 'the plant has gone' "$TMP/controller.log")" = 1
LAST=$(tail -1 "$TMP/cmds.txt")
AFTER=$(echo "$LAST - $T_KILL" | bc)
# 2000 sample times of 1 ms, plus a timer period and a loaded machine's delay
check "no command later than 2.5 s after the kill (the last: $AFTER s)" \
  test "$(echo "$AFTER < 2.5" | bc)" = 1
check "stale commands were sent before (the plant gone, not a crash of the controller)" \
  test "$(echo "$AFTER > 1.5" | bc)" = 1
if [ "$FAIL" = 0 ]; then
  echo "plant_lost: PASSED"
else
  grep -E "ERROR|WARN|exit" "$TMP/controller.log" | head -10 | sed 's/^/    /'
  echo "plant_lost: FAILED"
fi
exit "$FAIL"
