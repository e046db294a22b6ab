#!/usr/bin/env bash
# A lockstep plant in a nodelet manager starts only when its controller takes states
# (controller/ready, ~wait_for_controller), even when another subscriber in the manager made
# the subscriber count complete first: the controller's loader starts 3 s late (see
# test/ros/config/late_controller.launch). Checks: the run completes, no state was re-sent
# (without the wait, step 0 goes unanswered and is re-sent after ~resend_interval) and the
# first command answers step 0.
set -uo pipefail
TEST_NAME=late_controller
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
W=$(mktemp -d /tmp/pmrac_late_controller.XXXXXX)
export PMRAC_LATE_CONTROLLER_REPORT=$W/plant.json
"$ROOT/scripts/lib/launch_checked" --quiet --timeout 90 --log "$W/launch.log" \
  --expect-report "$W/plant.json" -- "$ROOT/test/ros/config/late_controller.launch" 2>"$W/err"
rc=$?
FAIL=0
if [ "$rc" != 0 ]; then
  echo "FAIL: launch_checked exit $rc"; sed 's/^/    /' "$W/err" | tail -15; FAIL=1
fi
if ! grep -Eq '"resent_states": ?0[,}]' "$W/plant.json" 2>/dev/null; then
  echo "FAIL: the plant re-sent states (it started before the controller took them): $(cut -c1-300 "$W/plant.json" 2>/dev/null)"
  grep "publishing its state again" "$W/launch.log" | head -3 | sed 's/^/    /'
  FAIL=1
fi
if [ "$FAIL" = 0 ]; then
  echo "ok: the plant waited for the late controller; run complete, nothing re-sent"
  echo "late_controller: PASSED"; rm -rf "$W"
else
  echo "late_controller: FAILED (logs in $W)"
fi
exit "$FAIL"
