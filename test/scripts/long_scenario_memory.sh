#!/usr/bin/env bash
# A plant's memory does not depend on the scenario's length: a scenario of the longest a run
# may be (until 86 400 s at dt 0.01: 8.64e6 steps, docs/reference/limits.md) starts like any
# other, in realtime (process shape) and lockstep (nodelet shape), and, with no controller,
# gives up after ~start_timeout (3 s) with exit 3 and its reason. A plant that reserved a
# latency sample per step (and lockstep a publication time per step) up front allocated in
# proportion to the scenario; longer scenarios are refused before anything is allocated.
set -uo pipefail
TEST_NAME=long_scenario_memory
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$(dirname "$0")/lib/launch_scratch.sh"
cat >"$TMP/long.yaml" <<'YAML'
scenario:
  name: long
  description: "theta = 0.5 (x ones), one day"
  theta:
    - {until: 86400, scale: 0.5}
  reference:
    - {until: 86400, r: 0.1}
YAML
for CASE in "realtime process" "lockstep nodelet"; do
  read -r CLOCK SHAPE <<<"$CASE"
  LOG=$TMP/$CLOCK.log
  RC=0
  "$ROOT/scripts/lib/launch_checked" --log "$LOG" --quiet --timeout 90 -- -p "$PORT" \
    preadaptive_mrac plant.launch scenario:="$TMP/long.yaml" dt:=0.01 clock:="$CLOCK" \
    shape:="$SHAPE" start_timeout:=3 output:=screen >/dev/null 2>"$TMP/$CLOCK.err" || RC=$?
  if [ "$RC" = 3 ] && grep -q "8640000 steps" "$LOG" && ! grep -qi "bad_alloc\|Failed to load" "$LOG"; then
    echo "ok: $CLOCK, $SHAPE shape: 8.64e6 steps start; no controller: exit 3"
  else
    echo "FAIL: $CLOCK, $SHAPE shape: exit $RC"
    grep -i "bad_alloc\|Failed to load\|steps of\|FATAL\|ERROR" "$LOG" | head -5 | sed 's/^/    /'
    FAIL=1
  fi
done
[ "$FAIL" = 0 ] && echo "long_scenario_memory: PASSED" || echo "long_scenario_memory: FAILED"
exit "$FAIL"
