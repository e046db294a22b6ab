#!/usr/bin/env bash
# Damaged and hostile recordings get a line naming the cause, never a traceback or a wrong
# diagnosis, and nothing recorded is lost or misnamed (no ROS master; a few seconds):
# - analyze_bag: a bag with one NaN command flags it on stderr ("warning: ... non-finite");
#   50 bytes flipped in the index, or 10 bits flipped over the file, say "corrupt bag" (not
#   "unindexed") and exit 2; a bag its recorder never closed says "unindexed"; --out naming an
#   existing file exits 2 with a line and leaves the file alone;
# - scripts/reindex_bags: a killed recording is recovered as <name>.incomplete.bag, which
#   analyze_bag warns about; a .bag.active that holds nothing recoverable, and one on a full
#   disk (a 400 KB tmpfs, as root; skipped otherwise), exit 1 and keep their .active name and
#   their bytes.
set -uo pipefail
TEST_NAME=hostile_bags
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
/usr/bin/python3 -c 'import rosbag' 2>/dev/null || skip "python3-rosbag not installed"
TMP=$(mktemp -d)
MNT=$TMP/full
cleanup() {
  mountpoint -q "$MNT" 2>/dev/null && umount "$MNT"
  rm -rf "$TMP"
}
trap cleanup EXIT
FAIL=0
check() {
  local name=$1
  shift
  if "$@"; then echo "ok: $name"; else echo "FAIL: $name"; FAIL=1; fi
}
PY=/usr/bin/python3
LIB=$ROOT/test/scripts/lib
analyze() { # FILE [ARGS...]: exit code in RC, stderr in $TMP/err
  RC=0
  "$PY" "$ROOT/scripts/analyze_bag" "$@" --no-figures >/dev/null 2>"$TMP/err" || RC=$?
}
no_traceback() { ! grep -q Traceback "$TMP/err"; }
said() { grep -q "$1" "$TMP/err"; }

"$PY" "$LIB/make_bag.py" "$TMP/good.bag"
"$PY" "$LIB/make_bag.py" "$TMP/nan.bag" --nan-at 100

analyze "$TMP/nan.bag" --out "$TMP/nan_out"
check "one NaN command: exit 0 and a warning naming it" \
  eval '[ "$RC" = 0 ] && said "warning: .*non-finite.*elevator_cmd u" && no_traceback'

for MODE in index spread; do
  "$PY" "$LIB/damage_bag.py" "$MODE" "$TMP/good.bag" "$TMP/$MODE.bag"
  analyze "$TMP/$MODE.bag" --out "$TMP/${MODE}_out"
  check "damaged ($MODE): exit 2, named corrupt, no traceback" \
    eval '[ "$RC" = 2 ] && said "corrupt bag" && ! said unindexed && no_traceback'
done
"$PY" "$LIB/damage_bag.py" killed "$TMP/good.bag" "$TMP/killed.bag"
analyze "$TMP/killed.bag" --out "$TMP/killed_out"
check "never closed: exit 2, named unindexed" eval '[ "$RC" = 2 ] && said unindexed && no_traceback'

echo keep >"$TMP/taken"
analyze "$TMP/good.bag" --out "$TMP/taken"
check "--out on an existing file: exit 2, one line, the file untouched" \
  eval '[ "$RC" = 2 ] && said "exists" && no_traceback && [ "$(cat "$TMP/taken")" = keep ]'
analyze "$TMP/good.bag" --out "$TMP/first"
SUM=$(md5sum <"$TMP/first/metrics.json")
analyze "$TMP/nan.bag" --out "$TMP/first"
check "--out on a folder with an earlier analysis: exit 2, one line, its metrics.json untouched" \
  eval '[ "$RC" = 2 ] && said "earlier analysis" && [ "$(grep -c . "$TMP/err")" = 1 ] && [ "$(md5sum <"$TMP/first/metrics.json")" = "$SUM" ]'
analyze "$TMP/nan.bag" --out "$TMP/first" --force
check "... replaced with --force" eval '[ "$RC" = 0 ] && [ "$(md5sum <"$TMP/first/metrics.json")" != "$SUM" ]'

mkdir "$TMP/rec"
cp "$TMP/killed.bag" "$TMP/rec/run.bag.active"
"$PY" "$LIB/damage_bag.py" garbage "$TMP/good.bag" "$TMP/rec/junk.bag.active"
JUNK_SUM=$(md5sum <"$TMP/rec/junk.bag.active")
RC=0
"$PY" "$ROOT/scripts/reindex_bags" "$TMP/rec" >"$TMP/reindex.out" 2>&1 || RC=$?
check "reindex_bags: exit 1 when one file is not recoverable" [ "$RC" = 1 ]
check "reindex_bags: the killed recording becomes run.incomplete.bag" \
  eval '[ -f "$TMP/rec/run.incomplete.bag" ] && [ ! -e "$TMP/rec/run.bag" ]'
check "reindex_bags: the unrecoverable file keeps its name and bytes" \
  eval '[ ! -e "$TMP/rec/junk.bag" ] && [ ! -e "$TMP/rec/junk.incomplete.bag" ] && [ "$(md5sum <"$TMP/rec/junk.bag.active")" = "$JUNK_SUM" ]'
analyze "$TMP/rec/run.incomplete.bag" --out "$TMP/rec_out"
check "analyze_bag warns about a recovered recording" eval '[ "$RC" = 0 ] && said "warning: .*incomplete recording"'

if [ "$(id -u)" = 0 ] && mkdir -p "$MNT" && mount -t tmpfs -o size=400k tmpfs "$MNT" 2>/dev/null; then
  cp "$TMP/killed.bag" "$MNT/run.bag.active"
  SUM=$(md5sum <"$MNT/run.bag.active")
  RC=0
  "$PY" "$ROOT/scripts/reindex_bags" "$MNT" >"$TMP/full.out" 2>&1 || RC=$?
  check "reindex_bags on a full disk: exit 1, the reason said, the recording untouched" \
    eval '[ "$RC" = 1 ] && grep -q "No space left" "$TMP/full.out" && [ "$(ls "$MNT")" = run.bag.active ] && [ "$(md5sum <"$MNT/run.bag.active")" = "$SUM" ]'
else
  echo "(full disk case skipped: needs root to mount a tmpfs)"
fi
[ "$FAIL" = 0 ] || { sed 's/^/    /' "$TMP/reindex.out" "$TMP/err"; }
[ "$FAIL" = 0 ] && echo "hostile_bags: PASSED" || echo "hostile_bags: FAILED"
exit "$FAIL"
