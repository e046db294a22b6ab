#!/usr/bin/env bash
# The speed hold of an ordinary JSBSim aircraft (plant.jsbsim.speed_hold, on by default): the
# Navion, flown from a user's folder with only plant.jsbsim.root, plant.jsbsim.aircraft and the
# operating point, through an alpha pulse of 0.02 rad for 3 s (20 s, theta 0):
#  1. with the default, the true airspeed stays within 2.5 m/s of the trim's (1.83 measured);
#  2. with plant.jsbsim.speed_hold=false (the throttle held at the trim, as before the hold) it
#     leaves 3 m/s (3.59 measured): the band is the hold's doing, not the scenario's;
#  3. the overlay's speed hold is refused, naming the key, for an aircraft without an engine;
#  4. no JSBSim process and no overlay folder is left.
set -uo pipefail
TEST_NAME=jsbsim_speed_hold
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
BUILD=${PMRAC_BUILD_DIR:-$ROOT/build}
FAIL=0
fail() {
  echo "FAIL: $*"
  FAIL=1
}
# shellcheck source=test/scripts/lib/jsbsim_mark.sh
source "$ROOT/test/scripts/lib/jsbsim_mark.sh"
[ -x "$BUILD/devel/bin/preadapt_sim" ] || { echo "SKIPPED: $TEST_NAME: build preadapt_sim first"; exit 77; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
run() { PMRAC_TEST_MARK=$JSBSIM_MARK PMRAC_JSBSIM=$JSBSIM_BIN TMPDIR=$TMP/tmp "$@"; }
mkdir -p "$TMP/tmp" "$TMP/my_aircraft/aircraft"
cp -r "$ROOT/jsbsim/aircraft/navion" "$TMP/my_aircraft/aircraft/navion"
KEYS=(--set plant.engine=jsbsim --set plant.jsbsim.root="$TMP/my_aircraft"
  --set plant.jsbsim.aircraft=navion --set plant.jsbsim.mach=0.1576
  --set plant.jsbsim.altitude_ft=0)
# An alpha pulse (0.02 rad for 3 s, then 0), theta 0: the climb it starts trades speed for
# height through the phugoid.
cat >"$TMP/pulse.yaml" <<'YAML'
scenario:
  name: alpha_pulse
  description: "alpha command 0.02 rad for 3 s, then 0; theta 0; 20 s"
  theta:
    - {until: 20.0, scale: 0.0}
  reference:
    - {until: 3.0, r: 0.02}
    - {until: 20.0, r: 0.0}
YAML

# The largest |airspeed - the first sample's| of a run's CSV [m/s].
drift() {
  /usr/bin/python3 - "$1" <<'PY'
import csv
import sys

v = [float(r["airspeed"]) for r in csv.DictReader(open(sys.argv[1]))]
print("%.3f" % max(abs(x - v[0]) for x in v))
PY
}

# 1. and 2.
for hold in default false; do
  extra=()
  [ "$hold" = false ] && extra=(--set plant.jsbsim.speed_hold=false)
  if ! run "$BUILD/devel/bin/preadapt_sim" --scenario "$TMP/pulse.yaml" --mode rac \
    "${KEYS[@]}" "${extra[@]}" --csv "$TMP/$hold.csv" >/dev/null 2>"$TMP/$hold.err"; then
    cat "$TMP/$hold.err"
    fail "preadapt_sim on the navion (speed hold $hold)"
    continue
  fi
  d=$(drift "$TMP/$hold.csv")
  echo "speed hold $hold: largest airspeed change from the trim $d m/s"
  if [ "$hold" = default ]; then
    /usr/bin/python3 -c "import sys; sys.exit(0 if $d < 2.5 else 1)" ||
      fail "with the speed hold the airspeed moved $d m/s from the trim (want < 2.5)"
  else
    /usr/bin/python3 -c "import sys; sys.exit(0 if $d > 3.0 else 1)" ||
      fail "with the throttle held the airspeed moved only $d m/s (want > 3: the band is the hold's)"
  fi
done

# 3. No engine: the speed hold is refused naming the key.
cp -r "$ROOT/jsbsim/aircraft/navion" "$TMP/my_aircraft/aircraft/glider"
mv "$TMP/my_aircraft/aircraft/glider/navion.xml" "$TMP/my_aircraft/aircraft/glider/glider.xml"
/usr/bin/python3 - "$TMP/my_aircraft/aircraft/glider/glider.xml" <<'PY'
import re
import sys

p = sys.argv[1]
s = open(p).read()
s = re.sub(r"<engine file=.*?</engine>", "", s, flags=re.S)
open(p, "w").write(s)
PY
run "$BUILD/devel/bin/preadapt_sim" --scenario "$TMP/pulse.yaml" --mode rac "${KEYS[@]}" \
  --set plant.jsbsim.aircraft=glider >/dev/null 2>"$TMP/glider.err"
echo "no engine: $(cat "$TMP/glider.err")"
grep -q "plant.jsbsim.speed_hold: the aircraft 'glider' has no <engine>" "$TMP/glider.err" ||
  fail "the aircraft without an engine was not refused naming plant.jsbsim.speed_hold"

# 4. Nothing of the runs is left.
[ -z "$(ls -A "$TMP/tmp")" ] || fail "left in the temporary folder: $(ls -A "$TMP/tmp")"
left=$(jsbsim_ours)
[ -z "$left" ] || fail "JSBSim processes left behind: $left"
if [ "$FAIL" = 0 ]; then echo "$TEST_NAME: PASSED"; else echo "$TEST_NAME: FAILED"; fi
exit "$FAIL"
