#!/usr/bin/env bash
# The recorder on a full disk (bag_dir on a 1 MB tmpfs; needs root, skipped otherwise), in
# lockstep and realtime: the run ends, and the recorder's last line names a file that exists
# and gives the real reason ("could not be written: ... No space left on device"), never
# "a plant stopped before its last step" alone. Before: `closed <name>.incomplete.bag` for a
# file that did not exist (a .bag.active was left), and in realtime the false reason.
set -uo pipefail
TEST_NAME=full_disk_recorder
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
[ "$(id -u)" = 0 ] || skip "needs root to mount a tmpfs"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$(dirname "$0")/lib/launch_scratch.sh"
MNT=$TMP/full
mkdir -p "$MNT"
mount -t tmpfs -o size=1m tmpfs "$MNT" || skip "cannot mount a tmpfs"
trap 'umount "$MNT" 2>/dev/null; rm -rf "$TMP"' EXIT
SCEN=$ROOT/test/ros/config/fault_scenario.yaml
for CLOCK in lockstep realtime; do
  LOG=$TMP/$CLOCK.log
  rm -rf "${MNT:?}"/*
  "$ROOT/scripts/lib/launch_checked" --log "$LOG" --quiet --timeout 150 -- -p "$PORT" \
    preadaptive_mrac scenario.launch scenario:="$SCEN" mode:=rac clock:="$CLOCK" \
    record:=true bag_dir:="$MNT/$CLOCK" output:=screen >/dev/null 2>&1
  LAST=$(grep -oE "recorder: (closed |could not close the bag).*" "$LOG" | tail -n1 | sed "s/^recorder: //")
  FILE=$(sed -E 's/^closed ([^ ;]+).*/\1/; s/^could not close the bag; what was written is in ([^ ;]+).*/\1/' <<<"$LAST")
  if [ -n "$LAST" ] && [ -f "$FILE" ] && grep -q "No space left" <<<"$LAST"; then
    echo "ok: $CLOCK: $(basename "$FILE") exists, the line says why: ${LAST:0:160}..."
  else
    echo "FAIL: $CLOCK: last line: ${LAST:-none}; files: $(find "$MNT" -type f | tr '\n' ' ')"
    FAIL=1
  fi
done
[ "$FAIL" = 0 ] && echo "full_disk_recorder: PASSED" || echo "full_disk_recorder: FAILED"
exit "$FAIL"
