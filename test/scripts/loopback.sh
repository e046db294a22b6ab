#!/usr/bin/env bash
# Network exposure: a single-machine run keeps every ROS socket on loopback. With ROS_IP and
# ROS_HOSTNAME unset (as a user who set nothing), a short realtime scenario.launch with the
# recorder runs through scripts/lib/launch_checked (which sources scripts/lib/ros_env), and
# while it runs every listening TCP socket and bound UDP socket of the run's processes
# (roslaunch, rosmaster, rosout, plant, controller, recorder, monitor: the process tree of the
# launch) must be on 127.0.0.1 (ss -ltnp / -lunp). Then the same check without the preload
# library (PMRAC_LOOPBACK_BIND=0) must SEE roscpp's XML-RPC servers on 0.0.0.0: the checker is
# checked, and the reason for the shim stays measured. Also a plain roslaunch typed without
# scripts/lib/ros_env: the nodes the launch file starts must be on loopback all the same.
#   Env: PMRAC_BUILD_DIR (default build).
set -uo pipefail
TEST_NAME=loopback
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
[ -f "$BUILD/devel/lib/libpmrac_loopback_bind.so" ] || skip "libpmrac_loopback_bind.so not built"
command -v ss >/dev/null || skip "ss not installed (apt-get install iproute2)"
export PMRAC_BUILD_DIR=$BUILD
W=$(mktemp -d "${TMPDIR:-/tmp}/loopback_test.XXXXXX")
LC_PID=""
cleanup() {
  [ -n "$LC_PID" ] && kill -INT -- "-$LC_PID" 2>/dev/null && sleep 2 && kill -KILL -- "-$LC_PID" 2>/dev/null
  rm -rf "$W"
}
trap cleanup EXIT
cat >"$W/short.yaml" <<YAML
scenario:
  name: loopback_short
  description: "12 s: theta 0.1, then 1 from 4 s"
  theta:
    - {until: 4.0, scale: 0.1}
    - {until: 12.0, scale: 1.0}
YAML
# shellcheck source=test/scripts/lib/counts.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib/counts.sh"

descendants() {  # pids of $1 and all its descendants
  local all
  all=$(ps -e -o pid=,ppid=)
  local todo=("$1") out=() p c
  while [ ${#todo[@]} -gt 0 ]; do
    p=${todo[0]}
    todo=("${todo[@]:1}")
    out+=("$p")
    for c in $(awk -v p="$p" '$2 == p { print $1 }' <<<"$all"); do todo+=("$c"); done
  done
  echo "${out[@]}"
}

# run NAME SHAPE [ENV=VALUE...]: one launch (shape:=process or nodelet); prints the sockets of
# its processes to $W/NAME.sockets as "PROTO ADDRESS:PORT PROCESS".
run() {
  local name=$1 shape=$2 port i pids
  shift 2
  port=$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
  (
    unset ROS_IP ROS_HOSTNAME LD_PRELOAD PMRAC_LOOPBACK_BIND
    export ROS_MASTER_URI=http://127.0.0.1:$port ROS_HOME=$W/$name/home ROS_LOG_DIR=$W/$name/log
    for kv in "$@"; do export "${kv?}"; done
    local args=(-p "$port" preadaptive_mrac scenario.launch scenario:="$W/short.yaml"
      clock:=realtime record:=true bag_dir:="$W/$name/bags" latency_report:="$W/$name/plant.json"
      output:=log shape:="$shape")
    if [ "${COMPARE:-0}" = 1 ]; then
      args=(-p "$port" preadaptive_mrac compare.launch scenario:="$W/short.yaml" clock:=realtime
        record:=true bag_dir:="$W/$name/bags" output:=log shape:="$shape")
    fi
    if [ "${PLAIN:-0}" = 1 ]; then
      # roslaunch typed by hand: no scripts/lib/ros_env, only what the launch file does.
      mkdir -p "$W/$name"
      exec setsid timeout --signal=INT 60 roslaunch "${args[@]}" >"$W/$name/launch.log" 2>&1
    fi
    exec setsid "$ROOT/scripts/lib/launch_checked" --quiet --timeout 60 --log "$W/$name/launch.log" \
      --expect-report "$W/$name/plant.json" -- "${args[@]}"
  ) &
  LC_PID=$!
  # Wait until the plant, controller and recorder are up: the recorder's progress topic is
  # advertised after all its subscriptions (in a nodelet manager, subscribers of a topic are
  # the manager, so they cannot be told apart), and the controller subscribes plant/state.
  local t0=$SECONDS
  while [ $((SECONDS - t0)) -lt 30 ]; do
    ROS_MASTER_URI=http://127.0.0.1:$port timeout 5 rostopic list 2>/dev/null |
      grep -q 'progress$' &&
      ROS_MASTER_URI=http://127.0.0.1:$port timeout 5 rostopic info "${STATUS_TOPIC:-/controller/status}" \
        2>/dev/null | grep -q 'Publishers:' && break
    sleep 0.3
  done
  sleep 1
  pids=$(descendants "$LC_PID")
  : >"$W/$name.sockets"
  for proto in t u; do
    ss -Hln"${proto}"p | while read -r _state _rq _sq local _peer procs; do
      for p in $pids; do
        if grep -q "pid=$p," <<<"$procs"; then
          echo "$proto $local $(sed 's/.*(("\([^"]*\)".*/\1/' <<<"$procs")" >>"$W/$name.sockets"
          break
        fi
      done
    done
  done
  wait "$LC_PID"
  RC=$?
  LC_PID=""
}

check_run() {  # NAME: the run ended well, its processes were seen, every socket on loopback
  local name=$1 n procs want others
  shift
  [ "$RC" = 0 ] && ok "$name: the run completed (exit 0)" ||
    bad "$name: the run failed: launch_checked exit $RC ($(tail -5 "$W/$name/launch.log"))"
  n=$(wc -l <"$W/$name.sockets")
  procs=$(awk '{print $3}' "$W/$name.sockets" | sort -u | tr '\n' ' ')
  # Every process of the run (a run seen without its nodes would pass vacuously).
  for want in "$@"; do
    grep -q " $want\$" "$W/$name.sockets" || bad "$name: no socket of $want seen (seen: $procs)"
  done
  if [ "$n" -ge 6 ]; then ok "$name: $n sockets of the run seen ($procs)"; else bad "$name: only $n sockets seen"; fi
  others=$(awk '$2 !~ /^127\.0\.0\.1:/ && $2 !~ /^\[::1\]:/' "$W/$name.sockets")
  if [ -z "$others" ]; then
    ok "$name: every socket of the run is on 127.0.0.1"
  else
    bad "$name: sockets not on loopback:"
    sed 's/^/    /' <<<"$others"
  fi
}

# One process per node: rosmaster, roslaunch, rosout, plant, controller, recorder, monitor.
run shim process
check_run shim rosmaster roslaunch rosout plant_sim_node mrac_controller bag_recorder_no
# The default shape: the nodes are nodelets in one pmrac_manager process.
run nodelet nodelet
check_run nodelet rosmaster roslaunch rosout pmrac_manager

# roslaunch typed by hand (no ros_env): scenario.launch's loopback arg (default true when neither
# ROS_IP nor ROS_HOSTNAME is set) keeps every node it starts on loopback. roslaunch, the master it
# starts and rosout exist before the launch file is read, so they follow the shell (the
# documented gap, docs/reference/ros.md "Network exposure"); they are left out of this check.
PLAIN=1 run plain process
PLAIN=0
grep -Ev " (rosmaster|roslaunch|rosout|python3?)\$" "$W/plain.sockets" >"$W/plain_nodes.sockets"
cp "$W/plain.sockets" "$W/plain_all.sockets"
mv "$W/plain_nodes.sockets" "$W/plain.sockets"
check_run plain plant_sim_node mrac_controller bag_recorder_no
# compare.launch typed by hand: its own loopback arg, the same rule.
PLAIN=1 COMPARE=1 STATUS_TOPIC=/pa/controller/status run compare process
PLAIN=0 COMPARE=0 STATUS_TOPIC=/controller/status
grep -Ev " (rosmaster|roslaunch|rosout|python3?)\$" "$W/compare.sockets" >"$W/compare_nodes.sockets"
mv "$W/compare_nodes.sockets" "$W/compare.sockets"
check_run compare plant_sim_node mrac_controller bag_recorder_no
# The checker sees a socket on another address: the same run without the shim.
run noshim process PMRAC_LOOPBACK_BIND=0
others=$(awk '$2 !~ /^127\.0\.0\.1:/ && $2 !~ /^\[::1\]:/' "$W/noshim.sockets")
if grep -q "^t 0.0.0.0:[0-9]* plant_sim_node" <<<"$others" &&
  grep -q "^t 0.0.0.0:[0-9]* mrac_controller" <<<"$others"; then
  ok "without the preload (PMRAC_LOOPBACK_BIND=0) the check sees roscpp's XML-RPC servers on 0.0.0.0 ($(wc -l <<<"$others") sockets)"
else
  bad "without the preload the check saw no 0.0.0.0 socket of plant/controller: $others"
fi

finish "loopback"
