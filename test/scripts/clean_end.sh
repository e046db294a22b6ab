#!/usr/bin/env bash
# a run that finishes normally ends quietly and says so. roslaunch printed a
# red "REQUIRED process [pmrac_manager-1] has died! process has finished cleanly" and the
# nodelet loaders warned "Couldn't find service /pmrac_manager/unload_nodelet". Now the node
# that ends the run asks roslaunch to stop (as Ctrl-C does). A short scenario through
# scenario.launch (both shapes) and compare.launch, plain roslaunch: exit 0, "the run has
# finished", no "has died", no REQUIRED, no unload warning, the bag closed under its name.
set -uo pipefail
TEST_NAME=clean_end
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$(dirname "$0")/lib/launch_scratch.sh"
SCEN=$ROOT/test/ros/config/short_scenario.yaml
for CASE in "scenario nodelet" "scenario process" "compare nodelet"; do
  read -r L SHAPE <<<"$CASE"
  LOG=$TMP/$L-$SHAPE.log
  RC=0
  timeout 120 roslaunch -p "$PORT" preadaptive_mrac "$L.launch" scenario:="$SCEN" shape:="$SHAPE" \
    record:=true bag_dir:="$TMP/bags-$L-$SHAPE" >"$LOG" 2>&1 || RC=$?
  WHY=""
  [ "$RC" = 0 ] || WHY="$WHY exit $RC;"
  grep -q "the run has finished: ending the launch" "$LOG" || WHY="$WHY no 'the run has finished';"
  grep -q "has died\|REQUIRED process" "$LOG" && WHY="$WHY a process reported as died;"
  grep -q "Couldn't find service" "$LOG" && WHY="$WHY unload warning;"
  [ -n "$(find "$TMP/bags-$L-$SHAPE" -name 'short_scenario_*.bag' ! -name '*.incomplete.bag')" ] ||
    WHY="$WHY no closed bag;"
  if [ -z "$WHY" ]; then
    echo "ok: $L.launch shape:=$SHAPE ends quietly"
  else
    echo "FAIL: $L.launch shape:=$SHAPE:$WHY"
    grep -E "WARN|died|REQUIRED|ERROR" "$LOG" | head -5
    FAIL=1
  fi
done
[ "$FAIL" = 0 ] && echo "clean_end: PASSED" || echo "clean_end: FAILED"
exit "$FAIL"
