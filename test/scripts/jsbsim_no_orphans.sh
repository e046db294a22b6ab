#!/usr/bin/env bash
# no JSBSim process outlives its run in ROS, whatever ends it. scenario.launch with
# plant_engine:=jsbsim (lockstep, scenario 1) is started twice on a master of its own:
#  1. nodelet shape: once the plant nodelet's JSBSim runs, pmrac_manager is SIGKILLed; its
#     JSBSim must be gone within 2 s (PR_SET_PDEATHSIG from a thread that lives as long as the
#     manager);
#  2. process shape: once plant_sim_node's JSBSim runs, the plant node is SIGKILLed; its
#     JSBSim must be gone within 2 s;
#  3. process shape: once plant_sim_node's JSBSim runs, roslaunch gets SIGINT (Ctrl-C); the
#     launch must end and its JSBSim be gone.
# The processes of this test carry a mark in their environment, so JSBSim processes of other
# runs on the machine do not count.
set -uo pipefail
TEST_NAME=jsbsim_no_orphans
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$ROOT/test/scripts/lib/launch_scratch.sh"
if [ -z "${PMRAC_JSBSIM:-}" ] && [ ! -x /usr/games/JSBSim ] && [ ! -x "$BUILD/jsbsim/bin/JSBSim" ]; then
  skip "no JSBSim binary (scripts/install_jsbsim)"
fi
MARK="jsbsim_no_orphans_$$_$(date +%s%N)"
export PMRAC_TEST_MARK=$MARK
# pids of processes named $1 (exactly) that carry this test's mark
marked() {
  local p
  for p in $(pgrep -x "$1"); do
    { tr '\0' '\n' <"/proc/$p/environ"; } 2>/dev/null | grep -qxF "PMRAC_TEST_MARK=$MARK" && echo "$p"
  done
}
# wait up to $2 s until `marked $1` is non-empty (wait_some) or empty (wait_gone)
wait_marked() {
  local end=$((SECONDS + $3))
  while [ $SECONDS -lt $end ]; do
    if [ -n "$(marked "$2")" ]; then [ "$1" = some ] && return 0; else [ "$1" = gone ] && return 0; fi
    sleep 0.1
  done
  return 1
}
wait_some() { wait_marked some "$1" "$2"; }
wait_gone() { wait_marked gone "$1" "$2"; }
launch() {
  roslaunch -p "$PORT" preadaptive_mrac scenario.launch plant_engine:=jsbsim mode:=rac \
    shape:="$1" output:=log >"$TMP/launch_$1.log" 2>&1 &
  LAUNCH=$!
}
stop_launch() {
  kill -INT "$LAUNCH" 2>/dev/null
  local end=$((SECONDS + 30))
  while kill -0 "$LAUNCH" 2>/dev/null && [ $SECONDS -lt $end ]; do sleep 0.2; done
  kill -0 "$LAUNCH" 2>/dev/null && kill -KILL "$LAUNCH"
  wait "$LAUNCH" 2>/dev/null
  return 0
}

# SIGKILL the process named $2 (the plant's: the manager, or the plant node) of a $1-shape
# launch once its JSBSim runs; the JSBSim must be gone within 2 s.
kill_mid_run() {
  launch "$1"
  check "$1: the plant's JSBSim runs" wait_some JSBSim 60
  local victim
  victim=$(marked "$2")
  check "$1: one $2" test "$(echo "$victim" | wc -w)" -eq 1
  kill -KILL "$victim"
  check "$1: JSBSim gone within 2 s of SIGKILL to $2" wait_gone JSBSim 2
  stop_launch
}
# 1. the nodelet manager SIGKILLed mid-run; 2. the plant node (process shape)
kill_mid_run nodelet pmrac_manager
kill_mid_run process plant_sim_node

# 3. Ctrl-C of the launch (process shape)
launch process
check "process: the plant's JSBSim runs" wait_some JSBSim 60
kill -INT "$LAUNCH"
end=$((SECONDS + 30))
while kill -0 "$LAUNCH" 2>/dev/null && [ $SECONDS -lt $end ]; do sleep 0.2; done
check "process: the launch ended on SIGINT" bash -c "! kill -0 $LAUNCH 2>/dev/null"
check "process: JSBSim gone after Ctrl-C" wait_gone JSBSim 5
stop_launch
left="$(marked JSBSim) $(marked pmrac_manager) $(marked plant_sim_node)"
if [ -n "${left// /}" ]; then
  echo "FAIL: left behind: $left"
  # shellcheck disable=SC2086 # a list of pids
  kill -KILL $left 2>/dev/null
  FAIL=1
fi
if [ "$FAIL" -ne 0 ]; then
  echo "$TEST_NAME: FAILED (logs: $TMP kept as $TMP.kept)"
  cp -r "$TMP" "$TMP.kept"
  exit 1
fi
echo "$TEST_NAME: passed"
