#!/usr/bin/env bash
# A realtime loop paused as a whole (plant and controller nodelets of one manager; SIGSTOP for
# 3 s, longer than ~plant_lost_samples' 2 s) goes on when it resumes: the controller counts only
# its own running time as the plant's silence, so it does not take the pause for a plant that
# has gone. Checks: the pause fell inside the run (the plant's closing line: more than 2500
# ticks came late, the 3 s it caught up on), no "the plant has gone", the launch ends with exit
# 0 and the bag holds every state.
set -uo pipefail
TEST_NAME=paused_with_plant
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$(dirname "$0")/lib/launch_scratch.sh"
command -v rostopic >/dev/null || skip "rostopic not installed"
# 10 s, so that the pause falls inside the run even when the first state is slow to be seen.
SCEN=$TMP/ten_seconds.yaml
cat >"$SCEN" <<'YAML'
scenario:
  name: ten_seconds
  description: "theta = 0.1 then 1 (x ones) from 1 s; 10 s"
  theta:
    - {until: 1.0, scale: 0.1}
    - {until: 10.0, scale: 1.0}
YAML

start_master
RC=0
timeout 120 roslaunch -p "$PORT" preadaptive_mrac scenario.launch scenario:="$SCEN" shape:=nodelet \
  clock:=realtime record:=true bag_dir:="$TMP/bags" >"$TMP/launch.log" 2>&1 &
LAUNCH=$!
cleanup() {
  kill -CONT "${MGR:-0}" 2>/dev/null
  kill -INT "$LAUNCH" 2>/dev/null
  sleep 1
  kill -9 "$LAUNCH" "$PM" 2>/dev/null
  rm -rf "$TMP"
}
trap cleanup EXIT
# The first state: the run (10 s) has begun; then the manager, plant and controller in it, stops.
timeout 60 rostopic echo -n 1 /plant/state >/dev/null 2>&1
# This launch's manager (its log under this test's ROS_HOME): other tests' launches may run
# beside this one (scripts/test's background lane), each with a manager of the same name.
MGR=$(pgrep -f "__name:=pmrac_manager __log:=$TMP/" | head -1)
[ -n "$MGR" ] || { echo "FAIL: no nodelet manager"; tail -20 "$TMP/launch.log"; exit 1; }
sleep 0.6
kill -STOP "$MGR"
sleep 3
kill -CONT "$MGR"
wait "$LAUNCH" || RC=$?
kill "$PM" 2>/dev/null
LOG=$TMP/launch.log
LATE=$(sed -n 's/.*scenario complete after .*, late ticks \([0-9]*\),.*/\1/p' "$LOG" | tail -1)
check "the pause fell inside the run (${LATE:-no} late ticks of the plant)" \
  test "${LATE:-0}" -gt 2500
check "the controller did not take the pause for a plant that has gone" \
  test "$(grep -c 'the plant has gone' "$LOG")" = 0
check "the launch ended with exit 0 (got $RC)" test "$RC" = 0
BAG=$(find "$TMP/bags" -name '*.bag' | head -1)
N=$(/usr/bin/python3 -c '
import sys, rosbag
with rosbag.Bag(sys.argv[1]) as b:
    print(b.get_message_count("/plant/state"))' "$BAG" 2>/dev/null || echo 0)
check "the bag holds every state of the run ($N of 10000)" test "$N" = 10000
if [ "$FAIL" = 0 ]; then
  echo "paused_with_plant: PASSED"
else
  grep -aE "WARN|ERROR|exit|complete" "$LOG" | sed 's/\x1b\[[0-9;]*m//g' | cut -c1-300 | head -20 |
    sed 's/^/    /'
  echo "paused_with_plant: FAILED"
fi
exit "$FAIL"
