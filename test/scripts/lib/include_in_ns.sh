# shellcheck shell=bash
# Sourced by the script tests that run a launch file of the package the way a user runs several
# at once: included in a namespace of their own.
#   include_in_ns OUT NS FILE [NAME=VALUE]...
# writes OUT: <launch><group ns="NS"><include file="$(find preadaptive_mrac)/launch/FILE">
# with one <arg name="NAME" value="VALUE"/> each.
include_in_ns() {
  local out=$1 ns=$2 file=$3 kv
  shift 3
  {
    echo "<launch>"
    echo "  <group ns=\"$ns\">"
    echo "    <include file=\"\$(find preadaptive_mrac)/launch/$file\">"
    for kv in "$@"; do echo "      <arg name=\"${kv%%=*}\" value=\"${kv#*=}\"/>"; done
    echo "    </include>"
    echo "  </group>"
    echo "</launch>"
  } >"$out"
}
