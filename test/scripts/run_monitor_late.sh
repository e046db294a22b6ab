#!/usr/bin/env bash
# The run monitor (compare.launch's required end of the launch) must learn that a plant
# completed even when it subscribed after the plant's last message: a lockstep run in a
# nodelet manager is not held for it and can end in a fraction of a second. The plant also
# publishes its last state latched on plant/done; the monitor reads it. Here the monitor
# starts 4 s after a scenario-1 run at dt 0.01 (0.2 s of work); the launch must end with 0.
# Without plant/done the monitor never sees the plant and the launch runs into the timeout.
set -uo pipefail
TEST_NAME=run_monitor_late
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
W=$(mktemp -d /tmp/pmrac_monitor_late.XXXXXX)
FAIL=0
for shape in process nodelet; do
  start=$(date +%s.%N)
  "$ROOT/scripts/lib/launch_checked" --quiet --timeout 60 --log "$W/$shape.log" -- \
    "$ROOT/test/ros/config/late_monitor.launch" shape:="$shape" 2>"$W/$shape.err"
  rc=$?
  took=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  if [ "$rc" = 0 ] && grep -q "run_monitor: all 1 plant(s) finished" "$W/$shape.log"; then
    echo "ok: $shape: the late monitor ended the launch with 0 after ${took} s"
  else
    echo "FAIL: $shape: launch_checked exit $rc after ${took} s (expected 0 and 'all 1 plant(s) finished')"
    sed 's/^/    /' "$W/$shape.err" | tail -20
    grep -E "run_monitor|ERROR|complete" "$W/$shape.log" | sed 's/^/    /' | tail -10
    FAIL=1
  fi
done
[ "$FAIL" = 0 ] && { echo "run_monitor_late: PASSED"; rm -rf "$W"; } || echo "run_monitor_late: FAILED (logs in $W)"
exit "$FAIL"
