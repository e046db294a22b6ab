#!/usr/bin/env bash
# scripts/lib/parent_names (compare.launch's pairs' launch-prefix) without ROS: from the node's
# namespace (ROS_NAMESPACE as roslaunch sets it, or a __ns:= argument) it replaces every
# argument equal to a NAME by PARENT/NAME and appends NAME:=PARENT/NAME; at the top level of a
# pair (/rac) the parent is the root; a node at the top level, an absolute or private NAME and
# a missing "--" are refused (exit 2, saying why).
set -uo pipefail
TEST_NAME=parent_names
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
PN=$ROOT/scripts/lib/parent_names
FAIL=0
# expect NAME WANT CMD...: CMD's stdout (one argument a line) equals WANT.
expect() {
  local name=$1 want=$2
  shift 2
  local got
  got=$("$@" 2>&1)
  if [ "$got" = "$want" ]; then
    echo "ok: $name"
  else
    echo "FAIL: $name: got [$got], want [$want]"
    FAIL=1
  fi
}
args=(pmrac_manager recorder/progress tf -- printf '%s\n' load preadaptive_mrac/PlantSim pmrac_manager --required __name:=plant_sim)
expect "nodelet loader in /my_run/rac" "load
preadaptive_mrac/PlantSim
/my_run/pmrac_manager
--required
__name:=plant_sim
pmrac_manager:=/my_run/pmrac_manager
recorder/progress:=/my_run/recorder/progress
tf:=/my_run/tf" env ROS_NAMESPACE=/my_run/rac "$PN" "${args[@]}"
expect "compare.launch at the top level (/rac): the names compare.launch always used" "load
preadaptive_mrac/PlantSim
/pmrac_manager
--required
__name:=plant_sim
pmrac_manager:=/pmrac_manager
recorder/progress:=/recorder/progress
tf:=/tf" env ROS_NAMESPACE=/rac "$PN" "${args[@]}"
expect "two levels deep, trailing slash" "x
tf:=/a/b/tf" env ROS_NAMESPACE=/a/b/pa/ "$PN" tf -- printf '%s\n' x
expect "__ns:= wins over ROS_NAMESPACE" "__ns:=/other/pa
tf:=/other/tf" env ROS_NAMESPACE=/my_run/rac "$PN" tf -- printf '%s\n' __ns:=/other/pa
expect "a node at the top level is refused" "parent_names: the node runs at the top level, there is no namespace above it
rc 2" bash -c 'env -u ROS_NAMESPACE "$0" tf -- true; echo "rc $?"' "$PN"
expect "an absolute name is refused" "parent_names: '/tf' is not a relative name
rc 2" bash -c 'ROS_NAMESPACE=/a/b "$0" /tf -- true; echo "rc $?"' "$PN"
expect "no command is refused" "usage: parent_names NAME... -- COMMAND [ARG...]
rc 2" bash -c 'ROS_NAMESPACE=/a/b "$0" tf; echo "rc $?"' "$PN"
[ "$FAIL" = 0 ] && echo "$TEST_NAME: PASSED" || echo "$TEST_NAME: FAILED"
exit "$FAIL"
