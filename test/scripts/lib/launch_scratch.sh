# shellcheck shell=bash
# Sourced after lib/ros_build.sh by the script tests that run launches of their own:
#   TMP            a scratch folder, removed at exit
#   PORT           a free port for the test's own master (ROS_MASTER_URI, ROS_HOME in TMP), every
#                  socket on loopback (scripts/lib/ros_env)
#   check NAME CONDITION...   runs CONDITION, prints "ok: NAME" or "FAIL: NAME" (then FAIL=1)
#   start_master   a master of the test's own on PORT (its pid in PM), answering when it returns
# shellcheck source=scripts/lib/ros_env
source "$ROOT/scripts/lib/ros_env"
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
PORT=$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
export ROS_MASTER_URI=http://127.0.0.1:$PORT ROS_HOME=$TMP/ros_home
FAIL=0
check() {
  local name=$1
  shift
  if "$@"; then echo "ok: $name"; else echo "FAIL: $name"; FAIL=1; fi
}
start_master() {
  rosmaster --core -p "$PORT" >"$TMP/master.log" 2>&1 &
  PM=$!
  for _ in $(seq 50); do
    timeout 5 rosparam list >/dev/null 2>&1 && break
    sleep 0.2
  done
}
