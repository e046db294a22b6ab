#!/usr/bin/env bash
# The package's second aircraft, jsbsim/aircraft/navion, is an ordinary JSBSim aircraft: it
# holds none of the package's properties, loads and trims in plain JSBSim at its reference
# condition (Nelson's sea-level 176 ft/s), and holds that trim for 10 s. No JSBSim process may
# be left behind.
set -uo pipefail
TEST_NAME=jsbsim_navion
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
FAIL=0
# This run's JSBSim processes carry a mark in their environment, so JSBSim processes of other
# runs on the machine do not count.
MARK="jsbsim_navion_$$_$(date +%s%N)"
ours() {
  local p
  for p in $(pgrep -x JSBSim); do
    tr '\0' '\n' <"/proc/$p/environ" 2>/dev/null | grep -qxF "PMRAC_TEST_MARK=$MARK" && echo "$p"
  done
}
if ! bin=$("$ROOT/scripts/install_jsbsim" | tail -n1) || [ ! -x "$bin" ]; then
  echo "FAIL: scripts/install_jsbsim did not give a JSBSim binary"
  echo "$TEST_NAME: FAILED"
  exit 1
fi
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
AIRCRAFT=$ROOT/jsbsim/aircraft/navion

# 1. Ordinary JSBSim form: nothing of the package's interface in the aircraft's files.
if grep -rl "pmrac" "$AIRCRAFT"; then
  echo "FAIL: the navion's files name the package's properties (above)"
  FAIL=1
fi

# 2. Plain JSBSim loads it from a copy of its folder alone and trims it.
mkdir -p "$TMP/root/aircraft"
cp -r "$AIRCRAFT" "$TMP/root/aircraft/navion"
cat >"$TMP/trim.xml" <<'XML'
<?xml version="1.0"?>
<runscript name="navion-trim">
  <use aircraft="navion" initialize="cruise_sl_176fps"/>
  <run start="0.0" end="10" dt="0.005">
    <event name="trim">
      <condition> simulation/sim-time-sec ge 0.0 </condition>
      <set name="simulation/do_simple_trim" value="0"/>
    </event>
    <event name="end">
      <condition> simulation/sim-time-sec ge 9.99 </condition>
      <notify>
        <property>aero/alpha-deg</property>
        <property>velocities/vt-fps</property>
        <property>position/h-sl-ft</property>
        <property>fcs/throttle-cmd-norm</property>
      </notify>
    </event>
  </run>
</runscript>
XML
(cd "$TMP" && PMRAC_TEST_MARK=$MARK timeout 30 "$bin" --root="$TMP/root" --script="$TMP/trim.xml" \
  --nohighlight >"$TMP/trim.log" 2>&1)
if ! grep -q "Trim successful" "$TMP/trim.log"; then
  grep -v '^\s*$' "$TMP/trim.log" | tail -8
  echo "FAIL: plain JSBSim did not trim the navion"
  FAIL=1
else
  # After 10 s from the trim: still level at 176 ft/s, sea level (within 0.5 ft/s, 5 ft).
  if ! /usr/bin/python3 - "$TMP/trim.log" <<'PY'; then
import re
import sys

text = open(sys.argv[1]).read()
end = text[text.find("end (Event 1)"):]
v = {k: float(x) for k, x in re.findall(r"(\S+) = (\S+)", end)}
print("after 10 s:", v)
ok = abs(v["velocities/vt-fps"] - 176.0) < 0.5 and abs(v["position/h-sl-ft"]) < 5.0
ok = ok and abs(v["aero/alpha-deg"]) < 1.0 and 0.2 < v["fcs/throttle-cmd-norm"] < 0.8
sys.exit(0 if ok else 1)
PY
    echo "FAIL: the navion did not hold its trim"
    FAIL=1
  fi
fi

left=$(ours)
if [ -n "$left" ]; then
  echo "FAIL: JSBSim processes left behind: $left"
  FAIL=1
fi
if [ "$FAIL" = 0 ]; then echo "$TEST_NAME: PASSED"; else echo "$TEST_NAME: FAILED"; fi
exit "$FAIL"
