#!/usr/bin/env bash
# plant (with the master and the recorder) and controller on two "hosts": two network
# namespaces joined by a veth pair (10.77.0.1/24 and 10.77.0.2/24), ROS_IP / ROS_MASTER_URI set
# in each, launched with launch/two_machines.launch part:=plant / part:=controller.
#  1. lockstep scenario 1 (pa_learn) through the link: the bag equals the batch CLI's CSV bit
#     for bit (bench/bag_vs_cli.py --tol 0: every step once, alpha and theta_hat identical),
#     with the launch file's caller-id guard (~accept_from) on and nothing dropped.
#  2. realtime (test/ros/config/fault_scenario.yaml, 14 s): the controller SIGSTOPped for 200 ms
#     then SIGCONTed, and later its link down for 300 ms then up: the plant holds trim (WARN
#     "holding trim", then "commands are back"), the controller goes stale on the link loss
#     ("no valid state", then "valid state again"), and the run completes (plant report).
#  4. both halves included in a user's namespace (<group ns="tm">, part:=plant in A and
#     part:=controller in B), lockstep short scenario recorded: the bag equals the CLI bit for
#     bit, the guard names the peer in the namespace (/tm/mrac_controller), no /use_sim_time.
# Needs root (CAP_NET_ADMIN): otherwise exit 77 with the reason. Traffic stays in the
# namespaces; they are deleted on exit.
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${PMRAC_BUILD_DIR:-$ROOT/build}
skip() { echo "SKIPPED: two_hosts: $*"; exit 77; }
[ -f "$BUILD/devel/setup.bash" ] || skip "$BUILD/devel/setup.bash not found (build first)"
command -v ip >/dev/null || skip "ip (iproute2) not installed"
[ "$(id -u)" = 0 ] || skip "not root: network namespaces need CAP_NET_ADMIN"
A=pmrac_a_$$ B=pmrac_b_$$ VA=pmva$$ VB=pmvb$$
PIDS=()
WORK=$(mktemp -d /tmp/pmrac_two_hosts.XXXXXX)
cleanup() {
  for p in "${PIDS[@]}"; do kill -TERM "$p" 2>/dev/null; done
  sleep 1
  for p in "${PIDS[@]}"; do kill -KILL "$p" 2>/dev/null; done
  ip netns del "$A" 2>/dev/null
  ip netns del "$B" 2>/dev/null
  rm -rf "$WORK"
}
trap cleanup EXIT
trap "exit 130" INT TERM
ip netns add "$A" 2>"$WORK/err" || skip "ip netns add failed: $(cat "$WORK/err")"
ip netns add "$B" || skip "second namespace refused"
ip link add "$VA" type veth peer name "$VB" 2>"$WORK/err" || skip "no veth: $(cat "$WORK/err")"
ip link set "$VA" netns "$A" && ip link set "$VB" netns "$B" || exit 1
ip -n "$A" addr add 10.77.0.1/24 dev "$VA" && ip -n "$B" addr add 10.77.0.2/24 dev "$VB" || exit 1
for ns in "$A" "$B"; do ip -n "$ns" link set lo up; done
ip -n "$A" link set "$VA" up && ip -n "$B" link set "$VB" up || exit 1

set +u
# shellcheck disable=SC1091
source "$BUILD/devel/setup.bash"
set -u
export ROS_MASTER_URI=http://10.77.0.1:11311 ROS_HOME="$WORK/ros"
# Two hosts: not the single-machine loopback set-up scripts/test sources (scripts/lib/ros_env):
# its preload would bind every server to 127.0.0.1, out of reach of the other namespace.
unset ROS_HOSTNAME LD_PRELOAD PMRAC_LOOPBACK_BIND
in_a() { ip netns exec "$A" env ROS_IP=10.77.0.1 "$@"; }
in_b() { ip netns exec "$B" env ROS_IP=10.77.0.2 "$@"; }
# In the background, as the process itself (exec), so $! is roslaunch's pid: a background
# subshell of a script ignores SIGINT, so processes are stopped with SIGTERM.
bg_a() { (exec ip netns exec "$A" env ROS_IP=10.77.0.1 "$@") & }
bg_b() { (exec ip netns exec "$B" env ROS_IP=10.77.0.2 "$@") & }
RC=0
fail() { echo "two_hosts: FAIL: $*"; RC=1; }

bg_a roscore -p 11311 >"$WORK/roscore.log" 2>&1
PIDS+=($!)
for _ in $(seq 100); do in_b /usr/bin/python3 /usr/bin/rosparam get /rosdistro >/dev/null 2>&1 && break; sleep 0.2; done
in_b /usr/bin/python3 /usr/bin/rosparam get /rosdistro >/dev/null 2>&1 || { echo "two_hosts: master unreachable from B"; exit 1; }

# run NAME ARGS...: plant half in A, controller half in B; waits for the plant's launch.
run() {
  local name=$1; shift
  bg_a roslaunch preadaptive_mrac two_machines.launch part:=plant plant_host:=10.77.0.1 \
    controller_host:=10.77.0.2 "$@" >"$WORK/$name.plant.log" 2>&1
  local pa=$!; PIDS+=($pa)
  for _ in $(seq 100); do grep -q "started core service\|process\[plant_sim" "$WORK/$name.plant.log" && break; sleep 0.1; done
  bg_b roslaunch preadaptive_mrac two_machines.launch part:=controller plant_host:=10.77.0.1 \
    controller_host:=10.77.0.2 "$@" >"$WORK/$name.controller.log" 2>&1
  CPID=$!; PIDS+=($CPID)
  PLANT_LAUNCH=$pa
}
# The controller's launch does not end by itself when the plant's run is over.
stop_controller() {
  kill -TERM "$CPID" 2>/dev/null
  timeout 20 tail --pid="$CPID" -f /dev/null
}
node_pid() { pgrep -n -f "__name:=$1"; }  # the newest: an earlier run's may still be ending

# 1. lockstep through the link, bag against the CLI.
echo "== lockstep scenario 1 through the veth link"
run lockstep clock:=lockstep record:=true bag:="$WORK/lockstep.bag" latency_report:="$WORK/lockstep.json"
timeout 400 tail --pid="$PLANT_LAUNCH" -f /dev/null
stop_controller
grep -Eq '"completed": ?true' "$WORK/lockstep.json" 2>/dev/null || fail "lockstep run did not complete ($(tail -3 "$WORK/lockstep.plant.log"))"
"$BUILD/devel/lib/preadaptive_mrac/preadapt_sim" --scenario 1 --mode pa_learn --csv "$WORK/cli.csv" >/dev/null
/usr/bin/python3 "$ROOT/bench/bag_vs_cli.py" "$WORK/lockstep.bag" "$WORK/cli.csv" --tol 0 || fail "bag differs from the CLI"
# The launch file's caller-id guard (~accept_from) was on, took the peer across the link and
# dropped nothing.
grep -q "taking commands on /controller/elevator_cmd only from /mrac_controller" "$WORK/lockstep.plant.log" ||
  fail "plant: no ~accept_from guard naming /mrac_controller"
grep -q "taking /plant/state only from /plant_sim" "$WORK/lockstep.controller.log" ||
  fail "controller: no ~accept_from guard naming /plant_sim"
! grep -q "dropping messages on" "$WORK"/lockstep.*.log || fail "the guard dropped messages of the loop"

# 2. realtime: controller host stalls, then its link goes down and up.
echo "== realtime: SIGSTOP 200 ms, link down 300 ms"
run realtime clock:=realtime scenario_file:="$ROOT/test/ros/config/fault_scenario.yaml" latency_report:="$WORK/realtime.json"
# Wait for the controller process (its log reaches the file only when roslaunch flushes it),
# then 3 s into the 14 s run.
for _ in $(seq 150); do [ -n "$(node_pid mrac_controller)" ] && break; sleep 0.1; done
sleep 3
CTL=$(node_pid mrac_controller)
[ -n "$CTL" ] || fail "no controller process"
kill -STOP "$CTL"; sleep 0.2; kill -CONT "$CTL"
sleep 2
ip -n "$B" link set "$VB" down; sleep 0.3; ip -n "$B" link set "$VB" up
timeout 60 tail --pid="$PLANT_LAUNCH" -f /dev/null
stop_controller
P="$WORK/realtime.plant.log" C="$WORK/realtime.controller.log"
grep -Eq '"completed": ?true' "$WORK/realtime.json" 2>/dev/null || fail "realtime run did not complete"
n=$(grep -c "holding trim (u = 0)" "$P"); [ "$n" -ge 2 ] || fail "plant held trim $n time(s), expected 2 (stall, link)"
grep -q "commands are back" "$P" || fail "plant never reported commands back"
grep -q "no valid state on" "$C" || fail "controller never went stale"
grep -q "valid state again" "$C" || fail "controller never recovered from staleness"
echo "plant: $(grep -c 'holding trim' "$P") trim episode(s); controller: $(grep -c 'no valid state on' "$C") stale episode(s); report: $(cat "$WORK/realtime.json" 2>/dev/null | cut -c1-200)"
# 3. a delayed link (tc netem), where the kernel has it: lockstep does not care how long a
# message takes, so a run at dt 0.01 through a link delayed by 2 ms each way gives the CLI's
# bag bit for bit, only slower.
echo "== lockstep scenario 1 at dt 0.01 through a link delayed by 2 ms each way (tc netem)"
if ip netns exec "$A" tc qdisc add dev "$VA" root netem delay 2ms 2>"$WORK/netem.err" &&
  ip netns exec "$B" tc qdisc add dev "$VB" root netem delay 2ms 2>>"$WORK/netem.err"; then
  run delayed clock:=lockstep dt:=0.01 record:=true bag:="$WORK/delayed.bag" latency_report:="$WORK/delayed.json"
  timeout 400 tail --pid="$PLANT_LAUNCH" -f /dev/null
  stop_controller
  grep -Eq '"completed": ?true' "$WORK/delayed.json" 2>/dev/null || fail "delayed lockstep run did not complete ($(tail -3 "$WORK/delayed.plant.log"))"
  "$BUILD/devel/lib/preadaptive_mrac/preadapt_sim" --scenario 1 --mode pa_learn --dt 0.01 --csv "$WORK/cli_delayed.csv" >/dev/null
  /usr/bin/python3 "$ROOT/bench/bag_vs_cli.py" "$WORK/delayed.bag" "$WORK/cli_delayed.csv" --tol 0 || fail "delayed-link bag differs from the CLI"
  echo "delayed link: $(cut -c1-200 "$WORK/delayed.json" 2>/dev/null)"
else
  echo "delayed link: not run, tc netem refused here ($(head -1 "$WORK/netem.err"))"
fi
# 4. both halves in a namespace of a user's launch file (what docs/reference/ros.md, "Namespaces", says
# two_machines.launch allows on both machines alike).
echo "== lockstep short scenario, both halves included in <group ns=\"tm\">"
SHORT=$ROOT/test/ros/config/short_scenario.yaml
for part in plant controller; do
  cat >"$WORK/tm_$part.launch" <<EOF
<launch><group ns="tm"><include file="\$(find preadaptive_mrac)/launch/two_machines.launch">
  <arg name="part" value="$part"/>
  <arg name="plant_host" value="10.77.0.1"/> <arg name="controller_host" value="10.77.0.2"/>
  <arg name="scenario_file" value="$SHORT"/>
  <arg name="record" value="true"/> <arg name="bag" value="$WORK/tm.bag"/>
  <arg name="latency_report" value="$WORK/tm.json"/>
</include></group></launch>
EOF
done
bg_a roslaunch "$WORK/tm_plant.launch" >"$WORK/tm.plant.log" 2>&1
PLANT_LAUNCH=$!
PIDS+=($PLANT_LAUNCH)
for _ in $(seq 100); do grep -q "process\[tm/plant_sim" "$WORK/tm.plant.log" && break; sleep 0.1; done
bg_b roslaunch "$WORK/tm_controller.launch" >"$WORK/tm.controller.log" 2>&1
CPID=$!
PIDS+=($CPID)
timeout 120 tail --pid="$PLANT_LAUNCH" -f /dev/null
stop_controller
grep -Eq '"completed": ?true' "$WORK/tm.json" 2>/dev/null ||
  fail "namespaced run did not complete ($(tail -3 "$WORK/tm.plant.log"))"
"$BUILD/devel/lib/preadaptive_mrac/preadapt_sim" --scenario "$SHORT" --mode pa_learn \
  --csv "$WORK/cli_tm.csv" >/dev/null
/usr/bin/python3 "$ROOT/bench/bag_vs_cli.py" "$WORK/tm.bag" "$WORK/cli_tm.csv" --ns /tm --tol 0 ||
  fail "namespaced bag differs from the CLI"
grep -q "taking commands on /tm/controller/elevator_cmd only from /tm/mrac_controller" \
  "$WORK/tm.plant.log" || fail "plant in /tm: no ~accept_from guard naming /tm/mrac_controller"
! grep -q "dropping messages on" "$WORK"/tm.*.log || fail "the guard dropped messages of the namespaced loop"
in_b /usr/bin/python3 /usr/bin/rosparam get /use_sim_time >/dev/null 2>&1 &&
  fail "/use_sim_time is set on the master"
if [ "$RC" != 0 ]; then
  for f in "$WORK"/*.log; do echo "---- $f"; grep -E "ERROR|WARN|FATAL|holding|stale|valid state" "$f" | tail -15; done
fi
[ "$RC" = 0 ] && echo "two_hosts: PASSED" || echo "two_hosts: FAILED"
exit "$RC"
