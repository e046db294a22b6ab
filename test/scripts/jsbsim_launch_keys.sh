#!/usr/bin/env bash
# scenario.launch flies a user's JSBSim aircraft given only its root, its name and the operating
# point, as a user types it (docs/tutorials/your_jsbsim_aircraft.md, section 3):
#  1. roslaunch ... plant_engine:=jsbsim jsbsim_root:=DIR jsbsim_aircraft:=navion jsbsim_mach:=M
#     jsbsim_altitude_ft:=H, no plant file of the user's: the run completes, both nodes say they
#     fly the aircraft's own elevator (travel and rate from its flight control system), the bag
#     is named _jsbsim_, and its error is preadapt_sim's with the same keys (the controller
#     designs on the paper's B-747 model in both);
#  2. jsbsim_aircraft alone (no plant_engine) is the JSBSim engine too, and jsbsim_elevator
#     reaches both nodes (roslaunch --dump-params);
#  3. elevator:=aircraft where there is no aircraft elevator to take (b747_pmrac, the linear
#     engine) is refused at start-up, exit code 2, naming ~elevator_from_aircraft and the cause;
#     an aircraft name that looks like a number (737) is taken as a name;
#  4. no JSBSim process and no overlay folder is left; the user's files are unchanged.
set -uo pipefail
TEST_NAME=jsbsim_launch_keys
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$ROOT/test/scripts/lib/launch_scratch.sh"
# shellcheck source=test/scripts/lib/jsbsim_mark.sh
source "$ROOT/test/scripts/lib/jsbsim_mark.sh"
[ -x "$BUILD/devel/bin/preadapt_sim" ] || skip "build preadapt_sim first"
export PMRAC_TEST_MARK=$JSBSIM_MARK PMRAC_JSBSIM=$JSBSIM_BIN TMPDIR=$TMP/tmp
mkdir -p "$TMPDIR"
USER_ROOT=$TMP/my_jsbsim
mkdir -p "$USER_ROOT/aircraft"
cp -r "$ROOT/jsbsim/aircraft/navion" "$USER_ROOT/aircraft/navion"
sums_before=$(cd "$USER_ROOT" && find . -type f -exec sha256sum {} + | sort)
# level_light's first two regimes (20 s): the Navion in level flight
cat >"$TMP/level_20s.yaml" <<'EOF'
scenario:
  name: level_20s
  description: "level_light's first 20 s: theta -0.1 then -0.5 (x ones) from 5 s; alpha +-0.01 rad every 2 s"
  theta:
    - {until: 5.0,  scale: -0.1}
    - {until: 20.0, scale: -0.5}
  reference:
    - {until:  2.0, r:  0.01}
    - {until:  4.0, r: -0.01}
    - {until:  6.0, r:  0.01}
    - {until:  8.0, r: -0.01}
    - {until: 10.0, r:  0.01}
    - {until: 12.0, r: -0.01}
    - {until: 14.0, r:  0.01}
    - {until: 16.0, r: -0.01}
    - {until: 18.0, r:  0.01}
    - {until: 20.0, r: -0.01}
EOF
KEYS=(jsbsim_root:="$USER_ROOT" jsbsim_aircraft:=navion jsbsim_mach:=0.1576 jsbsim_altitude_ft:=0)
WANT="derived at start: plant.actuator from the aircraft 'navion': travel 0.4363 rad, rate 1.0472 rad/s (<actuator> 'Elevator Actuator')"

# 1. The run, the user's way.
t0=$SECONDS
"$ROOT/scripts/lib/launch_checked" --log "$TMP/run.log" --timeout 120 -- -p "$PORT" \
  preadaptive_mrac scenario.launch plant_engine:=jsbsim "${KEYS[@]}" \
  scenario:="$TMP/level_20s.yaml" mode:=pa_robust record:=true bag_dir:="$TMP/bags"
rc=$?
echo "scenario.launch with the keys only: exit code $rc, $((SECONDS - t0)) s"
check "the launch flew the aircraft" test "$rc" = 0
check "the run completed" grep -q "scenario complete after 20000 of 20000 steps" "$TMP/run.log"
check "both nodes fly the navion's own elevator" test "$(grep -cF "$WANT" "$TMP/run.log")" = 2
BAG=$(ls "$TMP"/bags/level_20s_jsbsim_pa_robust_*.bag 2>/dev/null | head -1)
check "the bag is named for JSBSim" test -n "$BAG"
if [ -n "$BAG" ]; then
  "$BUILD/devel/bin/preadapt_sim" --scenario "$TMP/level_20s.yaml" --mode pa_robust \
    --set plant.engine=jsbsim --set plant.jsbsim.root="$USER_ROOT" \
    --set plant.jsbsim.aircraft=navion --set plant.jsbsim.mach=0.1576 \
    --set plant.jsbsim.altitude_ft=0 --json >"$TMP/sim.json" 2>"$TMP/sim.err" ||
    cat "$TMP/sim.err"
  /usr/bin/python3 - "$BAG" "$TMP/sim.json" <<'PY'
import json
import sys

import rosbag

steps, iae, dt = 0, 0.0, 0.001
with rosbag.Bag(sys.argv[1]) as bag:
    for _, m, _ in bag.read_messages(topics=["/controller/status"]):
        steps += 1
        iae += abs(m.e) * dt
sim = json.loads(open(sys.argv[2]).read().strip().splitlines()[-1])
print("ROS: %d controller steps, IAE %.9g; preadapt_sim: %d steps, IAE %.9g, overrides %s"
      % (steps, iae, sim["steps"], sim["iae"], sim["overrides"][:3]))
ok = steps == sim["steps"] == 20000 and abs(iae - sim["iae"]) <= 1e-6 * sim["iae"]
ok = ok and sim["overrides"][:3] == ["plant.actuator.enabled=true",
                                     "plant.actuator.max_deflection=0.43630000000000002",
                                     "plant.actuator.max_rate=1.0471999999999999"]
sys.exit(0 if ok else 1)
PY
  check "the ROS run's error is preadapt_sim's with the same keys" test $? = 0
fi

# 2. jsbsim_aircraft alone names the engine; jsbsim_elevator reaches both nodes.
roslaunch --dump-params preadaptive_mrac scenario.launch "${KEYS[@]}" jsbsim_elevator:=surface \
  >"$TMP/params.yaml" 2>&1
for node in plant_sim mrac_controller; do
  check "jsbsim_aircraft alone: $node flies JSBSim" grep -qx "/$node/plant/engine: jsbsim" "$TMP/params.yaml"
  check "jsbsim_aircraft alone: $node takes the aircraft's elevator" \
    grep -qx "/$node/elevator_from_aircraft: true" "$TMP/params.yaml"
  check "jsbsim_elevator:=surface: $node" grep -qx "/$node/plant/jsbsim/elevator: surface" "$TMP/params.yaml"
done

# 3. Refusals at start-up, naming the key and the cause.
refused() {  # NAME GREP-TEXT LAUNCH-ARGS...
  local name=$1 text=$2
  shift 2
  local t=$SECONDS
  "$ROOT/scripts/lib/launch_checked" --log "$TMP/$name.log" --timeout 60 -- -p "$PORT" \
    preadaptive_mrac scenario.launch scenario:="$TMP/level_20s.yaml" mode:=rac "$@" 2>/dev/null
  local code=$?
  echo "$name: exit code $code in $((SECONDS - t)) s: $(grep -m1 -F "$text" "$TMP/$name.log" | cut -c1-240)"
  check "$name: refused (exit code 2)" test "$code" = 2
  check "$name: the error names the cause" grep -qF "$text" "$TMP/$name.log"
}
refused b747_pmrac "elevator_from_aircraft: the aircraft 'b747_pmrac' carries the package's interface" \
  plant_engine:=jsbsim elevator:=aircraft
refused linear "elevator_from_aircraft: needs plant.engine jsbsim" elevator:=aircraft
refused numeric_name "cannot read the aircraft's elevator: plant.jsbsim.aircraft: no aircraft '737'" plant_engine:=jsbsim jsbsim_root:="$USER_ROOT" jsbsim_aircraft:=737
check "737 is taken as a name, not a number" bash -c "! grep -q 'expected a string' '$TMP/numeric_name.log'"

# 4. Nothing left.
check "the user's aircraft folder is unchanged" \
  test "$(cd "$USER_ROOT" && find . -type f -exec sha256sum {} + | sort)" = "$sums_before"
check "no overlay folder left" test -z "$(ls -A "$TMPDIR")"
check "no JSBSim process left" test -z "$(jsbsim_ours)"
if [ "$FAIL" = 0 ]; then echo "$TEST_NAME: PASSED"; else echo "$TEST_NAME: FAILED"; fi
exit "$FAIL"
