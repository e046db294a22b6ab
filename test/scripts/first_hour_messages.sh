#!/usr/bin/env bash
# messages a new user meets in the first hour name what is wrong.
# - scenario:=4 (neither 1-3 nor a YAML) through scenario.launch and compare.launch names the
#   valid choices (it said "file does not exist [4]");
# - bench/bag_vs_cli.py on a namespaced bag without --ns says the topics are not in the bag and
#   which --ns to try, exit 2 (it said "missing N ... -> DIFFERENT").
# The scenario key messages (a typo in a segment, a misspelt top-level section) are gtests
# (test_config).
set -uo pipefail
TEST_NAME=first_hour_messages
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$(dirname "$0")/lib/launch_scratch.sh"
for L in scenario compare; do
  timeout 60 roslaunch -p "$PORT" preadaptive_mrac "$L.launch" scenario:=4 >"$TMP/$L.log" 2>&1
  check "$L.launch scenario:=4 names the choices" \
    grep -q "scenario:=4 is neither 1, 2, 3 nor the path of a scenario YAML" "$TMP/$L.log"
done
/usr/bin/python3 - "$TMP/ns.bag" <<'PY'
import sys

import rosbag
import rospy
from preadaptive_mrac.msg import AdaptationStatus, PlantState

with rosbag.Bag(sys.argv[1], 'w') as bag:
    for k in range(3):
        t = rospy.Time(1 + k)
        bag.write('/rac/plant/state', PlantState(step=k), t)
        bag.write('/rac/controller/status', AdaptationStatus(step=k), t)
PY
printf 't,x1,theta_hat0,theta_hat1,theta_hat2\n0,0,0,0,0\n0.001,0,0,0,0\n0.002,0,0,0,0\n' >"$TMP/cli.csv"
RC=0
/usr/bin/python3 "$ROOT/bench/bag_vs_cli.py" "$TMP/ns.bag" "$TMP/cli.csv" >"$TMP/bvc.log" 2>&1 || RC=$?
check "bag_vs_cli without --ns: exit 2" [ "$RC" = 2 ]
check "bag_vs_cli without --ns: says the topics are not in the bag and names --ns /rac" \
  grep -q "/plant/state and /controller/status not in .*try --ns /rac" "$TMP/bvc.log"
RC=0
/usr/bin/python3 "$ROOT/bench/bag_vs_cli.py" "$TMP/ns.bag" "$TMP/cli.csv" --ns /rac >"$TMP/bvc_ns.log" 2>&1 || RC=$?
check "bag_vs_cli --ns /rac: EQUAL" grep -q "EQUAL" "$TMP/bvc_ns.log"
if [ "$FAIL" != 0 ]; then
  tail -n 5 "$TMP"/*.log
  echo "first_hour_messages: FAILED"
  exit 1
fi
echo "first_hour_messages: PASSED"
