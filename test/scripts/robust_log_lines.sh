#!/usr/bin/env bash
# pa_robust re-verifies every few ms inside a phase, and the controller logged
# each of those DECISION events at INFO (dozens of lines per switch). Now the same choice again
# is DEBUG: over lockstep scenario 1 at most two INFO decision lines per onset (the onset's
# choice and, at most, one change), while the attention topic still carries every DECISION event.
set -uo pipefail
TEST_NAME=robust_log_lines
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$(dirname "$0")/lib/launch_scratch.sh"
RC=0
"$ROOT/scripts/lib/launch_checked" --log "$TMP/launch.log" --timeout 300 \
  --expect-report "$TMP/plant.json" -- -p "$PORT" preadaptive_mrac scenario.launch scenario:=1 \
  mode:=pa_robust record:=true bag_dir:="$TMP/bags" latency_report:="$TMP/plant.json" \
  >/dev/null 2>&1 || RC=$?
[ "$RC" = 0 ] || { echo "FAIL: the run failed (exit $RC)"; tail -n 20 "$TMP/launch.log"; exit 1; }
ONSETS=$(grep -c "s: onset (" "$TMP/launch.log")
INFO_DECISIONS=$(grep -c "INFO.*s: decision (" "$TMP/launch.log")
EVENTS=$(/usr/bin/python3 - "$TMP"/bags/*.bag <<'PY'
import sys

import rosbag

with rosbag.Bag(sys.argv[1]) as bag:
    print(sum(m.type_name == 'decision' for _, m, _ in bag.read_messages(['/controller/attention'])))
PY
)
echo "onsets $ONSETS, INFO decision lines $INFO_DECISIONS, DECISION events on the topic $EVENTS"
if [ "$ONSETS" -gt 0 ] && [ "$INFO_DECISIONS" -le $((2 * ONSETS)) ] && [ "$EVENTS" -gt $((2 * ONSETS)) ]; then
  echo "robust_log_lines: PASSED"
  exit 0
fi
echo "robust_log_lines: FAILED"
exit 1
