# shellcheck shell=bash
# The PASS/FAIL counters of the script tests that count their checks:
#   ok MESSAGE...    prints "PASS: MESSAGE", counts a pass
#   bad MESSAGE...   prints "FAIL: MESSAGE", counts a failure
#   finish NAME      prints "NAME: P passed, F failed"; its status (the script's, as its last
#                    command) is 0 only when nothing failed and at least one check passed, so a
#                    test that skipped every check by mistake does not pass.
PASS=0
FAIL=0
ok() {
  echo "PASS: $*"
  PASS=$((PASS + 1))
}
bad() {
  echo "FAIL: $*"
  FAIL=$((FAIL + 1))
}
finish() {
  echo "$1: $PASS passed, $FAIL failed"
  [ "$FAIL" = 0 ] && [ "$PASS" -gt 0 ]
}
