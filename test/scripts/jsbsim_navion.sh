#!/usr/bin/env bash
# The package's second aircraft, jsbsim/aircraft/navion, is an ordinary JSBSim aircraft (none of
# the package's properties) and the package flies it from a user's folder unchanged:
#  1. plain JSBSim loads a copy of the folder alone, trims it at Nelson's sea-level 176 ft/s and
#     it holds that trim for 10 s;
#  2. preadapt_trim, given only plant.jsbsim.root, plant.jsbsim.aircraft and the operating point,
#     gives a plant file: engine jsbsim, the aircraft's elevator travel and rate from its flight
#     control system, and A, B within 5 % of Nelson's short period (docs/tutorials/own_aircraft.md);
#  3. preadapt_sim flies scenario 1's first two regimes (theta 0.1 then 1, r 0.1 rad, 20 s) on it
#     with the same keys, and knows the aircraft's elevator limits; preadapt_family, given the
#     same keys and no --elevator, flies the aircraft's elevator too (not the B-747's), and so
#     do both nodes of scenario.launch given preadapt_trim's plant file and plant_engine:=jsbsim;
#  4. an aircraft without an elevator the package can find is refused within 2 s naming the cause;
#  5. the user's files are unchanged, and no JSBSim process and no overlay folder is left.
set -uo pipefail
TEST_NAME=jsbsim_navion
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
BUILD=${PMRAC_BUILD_DIR:-$ROOT/build}
FAIL=0
fail() {
  echo "FAIL: $*"
  FAIL=1
}
# shellcheck source=test/scripts/lib/jsbsim_mark.sh
source "$ROOT/test/scripts/lib/jsbsim_mark.sh"
for tool in preadapt_trim preadapt_sim preadapt_family; do
  [ -x "$BUILD/devel/bin/$tool" ] || { echo "SKIPPED: $TEST_NAME: build $tool first"; exit 77; }
done
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
AIRCRAFT=$ROOT/jsbsim/aircraft/navion
# Every JSBSim started here carries the mark; every overlay lands in $TMP/tmp.
run() { PMRAC_TEST_MARK=$JSBSIM_MARK PMRAC_JSBSIM=$JSBSIM_BIN TMPDIR=$TMP/tmp "$@"; }
mkdir -p "$TMP/tmp"

# 1. Ordinary JSBSim form.
grep -rl "pmrac" "$AIRCRAFT" && fail "the navion's files name the package's properties (above)"
USER_ROOT=$TMP/my_aircraft
mkdir -p "$USER_ROOT/aircraft"
cp -r "$AIRCRAFT" "$USER_ROOT/aircraft/navion"
sums_before=$(cd "$USER_ROOT" && find . -type f -exec sha256sum {} + | sort)
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
(cd "$TMP" && run timeout 30 "$JSBSIM_BIN" --root="$USER_ROOT" --script="$TMP/trim.xml" \
  --nohighlight >"$TMP/trim.log" 2>&1)
if ! grep -q "Trim successful" "$TMP/trim.log"; then
  grep -v '^\s*$' "$TMP/trim.log" | tail -8
  fail "plain JSBSim did not trim the navion"
elif ! /usr/bin/python3 - "$TMP/trim.log" <<'PY'; then
import re
import sys

text = open(sys.argv[1]).read()
end = text[text.find("end (Event 1)") :]
v = {k: float(x) for k, x in re.findall(r"(\S+) = (\S+)", end)}
print("plain JSBSim, 10 s after the trim:", v)
ok = abs(v["velocities/vt-fps"] - 176.0) < 0.5 and abs(v["position/h-sl-ft"]) < 5.0
ok = ok and abs(v["aero/alpha-deg"]) < 1.0 and 0.2 < v["fcs/throttle-cmd-norm"] < 0.8
sys.exit(0 if ok else 1)
PY
  fail "the navion did not hold its trim in plain JSBSim"
fi

# 2. preadapt_trim from the user's folder: the keys of the aircraft and the operating point only.
KEYS=(--set plant.jsbsim.root="$USER_ROOT" --set plant.jsbsim.aircraft=navion)
if ! run "$BUILD/devel/bin/preadapt_trim" "${KEYS[@]}" --mach 0.1576 --altitude-ft 0 \
  >"$TMP/navion_trimmed.yaml" 2>"$TMP/trim.err"; then
  cat "$TMP/trim.err"
  fail "preadapt_trim on the navion"
elif ! /usr/bin/python3 - "$TMP/navion_trimmed.yaml" <<'PY'; then
import sys

import yaml

p = yaml.safe_load(open(sys.argv[1]))["plant"]
A, B = p["A"], p["B"]
print("preadapt_trim: A", A[1], A[2], "B", B, "actuator", p.get("actuator"))
# Nelson's Navion short period (docs/tutorials/own_aircraft.md, section 4).
want = {"A11": (A[1][1], -2.02), "A12": (A[1][2], 1.0), "A21": (A[2][1], -6.98),
        "A22": (A[2][2], -2.95), "B1": (B[1], -0.160), "B2": (B[2], -11.73)}
bad = [k for k, (got, ref) in want.items() if abs(got - ref) > 0.05 * abs(ref)]
act = p.get("actuator") or {}
bad += [] if act.get("enabled") and abs(act.get("max_deflection", 0) - 0.4363) < 1e-9 else ["travel"]
bad += [] if abs(act.get("max_rate", 0) - 1.0472) < 1e-9 else ["rate"]
bad += [] if p["engine"] == "jsbsim" and p["jsbsim"]["aircraft"] == "navion" else ["keys"]
print("off:", bad)
sys.exit(1 if bad else 0)
PY
  fail "preadapt_trim's plant file is not the Navion's (above)"
fi

# 3. preadapt_sim: scenario 1's first two regimes, the same keys and the operating point.
cat >"$TMP/scenario1_20s.yaml" <<'EOF2'
scenario:
  name: scenario1_20s
  description: "scenario 1's first two regimes: theta = 0.1, then 1 (x ones) from 5 s; r 0.1 rad"
  theta:
    - {until: 5.0,  scale: 0.1}
    - {until: 20.0, scale: 1.0}
  reference:
    - {until: 20.0, r: 0.1}
EOF2
if ! run "$BUILD/devel/bin/preadapt_sim" --scenario "$TMP/scenario1_20s.yaml" --mode rac \
  --set plant.engine=jsbsim "${KEYS[@]}" --set plant.jsbsim.mach=0.1576 \
  --set plant.jsbsim.altitude_ft=0 --json >"$TMP/sim.json" 2>"$TMP/sim.err"; then
  cat "$TMP/sim.err"
  fail "preadapt_sim on the navion"
elif ! /usr/bin/python3 - "$TMP/sim.json" <<'PY'; then
import json
import sys

d = json.loads(open(sys.argv[1]).read().strip().splitlines()[-1])
print("preadapt_sim:", d["steps"], "steps, IAE", d["iae"], "overrides", d["overrides"])
want = ["plant.actuator.enabled=true", "plant.actuator.max_deflection=0.43630000000000002",
        "plant.actuator.max_rate=1.0471999999999999"]
sys.exit(0 if d["steps"] == 20000 and d["overrides"][:3] == want else 1)
PY
  fail "preadapt_sim's run on the navion (above)"
fi

# A family of one scenario on the same keys: the aircraft's elevator by default.
if ! run "$BUILD/devel/bin/preadapt_family" --seed 7 --count 1 --regimes 1 --segments 2 \
  --modes rac --set plant.engine=jsbsim "${KEYS[@]}" --set plant.jsbsim.mach=0.1576 \
  --set plant.jsbsim.altitude_ft=0 --json >"$TMP/family.out" 2>"$TMP/family.err"; then
  cat "$TMP/family.err"
  fail "preadapt_family on the navion"
elif ! /usr/bin/python3 - "$TMP/family.out" <<'PY'; then
import json
import sys

e = json.loads(open(sys.argv[1]).read().strip().splitlines()[-1])["elevator"]
print("preadapt_family: elevator", e)
sys.exit(0 if e["preset"] == "aircraft" and e["enabled"] and e["max_deflection"] == 0.4363
         and e["max_rate"] == 1.0472 else 1)
PY
  fail "preadapt_family did not fly the navion's own elevator (above)"
fi

# scenario.launch with the plant file and plant_engine:=jsbsim: both nodes get the aircraft's
# elevator (roslaunch --dump-params: the parameters as the launch sets them, no master).
if command -v roslaunch >/dev/null; then
  roslaunch --dump-params preadaptive_mrac scenario.launch plant_engine:=jsbsim \
    plant_config:="$TMP/navion_trimmed.yaml" >"$TMP/params.yaml" 2>"$TMP/params.err" ||
    fail "roslaunch --dump-params: $(tail -3 "$TMP/params.err")"
  for node in plant_sim mrac_controller; do
    got=$(grep -E "^/$node/plant/actuator/(enabled|max_deflection|max_rate):" "$TMP/params.yaml" | tr '\n' ' ')
    echo "scenario.launch, $node: $got"
    [ "$got" = "/$node/plant/actuator/enabled: true /$node/plant/actuator/max_deflection: 0.4363 /$node/plant/actuator/max_rate: 1.0472 " ] ||
      fail "scenario.launch gives $node another elevator than the navion's"
  done
else
  fail "roslaunch not found: source the build's devel/setup.bash"
fi

# 4. No elevator the package can find: refused at once, naming it.
cp -r "$AIRCRAFT" "$USER_ROOT/aircraft/noelevator"
mv "$USER_ROOT/aircraft/noelevator/navion.xml" "$USER_ROOT/aircraft/noelevator/noelevator.xml"
sed -i 's|<output>fcs/elevator-pos-rad</output>|<output>fcs/elevator-pos-x</output>|' \
  "$USER_ROOT/aircraft/noelevator/noelevator.xml"
t0=$(date +%s%N)
run "$BUILD/devel/bin/preadapt_trim" --set plant.jsbsim.root="$USER_ROOT" \
  --set plant.jsbsim.aircraft=noelevator >/dev/null 2>"$TMP/noel.err"
rc=$?
ms=$((($(date +%s%N) - t0) / 1000000))
echo "no elevator: exit code $rc in $ms ms: $(cat "$TMP/noel.err")"
grep -q "plant.jsbsim.aircraft: the aircraft 'noelevator' has no elevator the package can find" \
  "$TMP/noel.err" || fail "the aircraft without an elevator was not refused naming the cause"
if [ "$rc" != 1 ] || [ "$ms" -ge 2000 ]; then
  fail "the refusal took $ms ms or exit code $rc (want 1, < 2 s)"
fi
rm -rf "$USER_ROOT/aircraft/noelevator"

# 5. Nothing of the runs is left.
[ "$(cd "$USER_ROOT" && find . -type f -exec sha256sum {} + | sort)" = "$sums_before" ] ||
  fail "the user's aircraft folder was changed"
[ -z "$(ls -A "$TMP/tmp")" ] || fail "left in the temporary folder: $(ls -A "$TMP/tmp")"
left=$(jsbsim_ours)
[ -z "$left" ] || fail "JSBSim processes left behind: $left"
if [ "$FAIL" = 0 ]; then echo "$TEST_NAME: PASSED"; else echo "$TEST_NAME: FAILED"; fi
exit "$FAIL"
