#!/usr/bin/env bash
# a launch refused at start-up (mode:=pa_lern, record:=true) left an empty
# 4 KB bag named like a real run (<scenario>_pa_lern_<date>.bag). A refused run must leave
# nothing that looks like data: no .bag (and no .bag.active) in bag_dir, in both shapes and
# through scenario.launch and compare.launch (where the /rac pair may have run some steps before
# /pa's refusal ended the launch: at most a <name>.incomplete.bag); scripts/lib/launch_checked
# exits 2 (the manager used to die of SIGTRAP now and then on its way out: exit 1).
set -uo pipefail
TEST_NAME=refused_launch_no_bag
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$(dirname "$0")/lib/launch_scratch.sh"
for CASE in "scenario mode nodelet" "scenario mode process" "compare pa_mode nodelet"; do
  read -r L ARG SHAPE <<<"$CASE"
  BAGS=$TMP/$L-$SHAPE
  RC=0
  "$ROOT/scripts/lib/launch_checked" --log "$TMP/$L-$SHAPE.log" --quiet --timeout 60 -- \
    -p "$PORT" preadaptive_mrac "$L.launch" "$ARG":=pa_lern record:=true bag_dir:="$BAGS" \
    shape:="$SHAPE" output:=log >/dev/null 2>&1 || RC=$?
  LEFT=$(find "$BAGS" -name "*.bag*" ! -name "*.incomplete.bag" 2>/dev/null)
  if [ "$RC" = 2 ] && [ -z "$LEFT" ]; then
    echo "ok: $L.launch $ARG:=pa_lern shape:=$SHAPE: exit $RC, no bag left"
  else
    echo "FAIL: $L.launch $ARG:=pa_lern shape:=$SHAPE: exit $RC, left: ${LEFT:-nothing}"
    FAIL=1
  fi
done
[ "$FAIL" = 0 ] && echo "refused_launch_no_bag: PASSED" || echo "refused_launch_no_bag: FAILED"
exit "$FAIL"
