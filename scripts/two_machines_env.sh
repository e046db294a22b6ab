#!/usr/bin/env bash
# env-loader of launch/two_machines.launch: roslaunch runs it over ssh on the remote machine
# with the node's command line as arguments. It must set up that machine's ROS environment
# and its own address (ROS_IP), then run the command. Adapt the two paths/values below, or
# set PMRAC_SETUP / PMRAC_ROS_IP in the remote account's environment.
set -e
# shellcheck disable=SC1090
source "${PMRAC_SETUP:-$HOME/preadaptive_mrac/build/devel/setup.bash}"
# The address the other machine reaches this one at (the first non-loopback one by default).
export ROS_IP="${PMRAC_ROS_IP:-$(hostname -I | awk '{print $1}')}"
unset ROS_HOSTNAME
exec "$@"
