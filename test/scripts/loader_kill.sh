#!/usr/bin/env bash
# The plant's nodelet loader killed with SIGKILL mid-run (the default nodelet shape, with
# record:=true), in realtime and in lockstep: the launch ends within seconds (exit 3, the plant
# saying it was unloaded before its run ended) and the bag is closed as <name>.incomplete.bag.
# Before, the manager unloaded the plant through the bond and went on: in realtime the
# controller kept sending stale commands and the recorder writing them, and the launch never
# ended (nor did it in lockstep).
set -uo pipefail
TEST_NAME=loader_kill
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$(dirname "$0")/lib/launch_scratch.sh"
SCEN=$ROOT/test/ros/config/fault_scenario.yaml
for CLOCK in realtime lockstep; do
  BAGS=$TMP/bags_$CLOCK
  LOG=$TMP/$CLOCK.log
  "$ROOT/scripts/lib/launch_checked" --log "$LOG" --quiet --timeout 150 -- -p "$PORT" \
    preadaptive_mrac scenario.launch scenario:="$SCEN" mode:=rac clock:="$CLOCK" dt:=0.001 \
    record:=true bag_dir:="$BAGS" output:=screen >/dev/null 2>"$TMP/$CLOCK.err" &
  LAUNCH=$!
  # The plant's loader of this launch (its log folder is this test's).
  PID=""
  for _ in $(seq 1 1200); do
    if grep -q "steps of" "$LOG" 2>/dev/null && ls "$BAGS"/*.bag.active >/dev/null 2>&1; then
      PID=$(pgrep -f "load preadaptive_mrac/PlantSim .*$TMP" | head -n1)
      [ -n "$PID" ] && break
    fi
    sleep 0.1
  done
  if [ -z "$PID" ]; then
    echo "FAIL: $CLOCK: the run did not start"; FAIL=1
    RL=$(pgrep -f "roslaunch -p $PORT " | head -n1); [ -n "$RL" ] && kill -INT "$RL"; wait "$LAUNCH"; continue
  fi
  sleep 1
  kill -9 "$PID"
  T0=$(date +%s)
  RC=0
  wait "$LAUNCH" || RC=$?
  SECS=$(($(date +%s) - T0))
  INCOMPLETE=$(ls "$BAGS"/*.incomplete.bag 2>/dev/null | head -n1)
  if [ "$RC" = 3 ] && [ "$SECS" -le 60 ] && [ -n "$INCOMPLETE" ] && grep -q "unloaded before its run ended" "$LOG"; then
    echo "ok: $CLOCK: loader killed, launch ended after ${SECS} s (exit 3), $(basename "$INCOMPLETE")"
  else
    echo "FAIL: $CLOCK: launch exit $RC after ${SECS} s, bags: $(ls "$BAGS" 2>/dev/null | tr '\n' ' ')"
    grep -E "ERROR|FATAL|closed" "$LOG" | tail -5 | sed 's/^/    /'
    FAIL=1
  fi
done
[ "$FAIL" = 0 ] && echo "loader_kill: PASSED" || echo "loader_kill: FAILED"
exit "$FAIL"
