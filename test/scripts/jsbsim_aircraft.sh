#!/usr/bin/env bash
# the JSBSim binary installs without FlightGear (scripts/install_jsbsim), the
# package's aircraft jsbsim/aircraft/b747_pmrac loads, JSBSim's own trim holds Mach 0.8 at
# 40,000 ft, and the short-period model identified from a 1 ms socket lockstep run is within 2 %
# of Heffley and Jewell's condition 9 (jsbsim/tools/jsbsim_probe.py linearise --check). Its speed
# motion is the published one: flown in plain JSBSim (no socket, about a second per condition) at
# Heffley and Jewell's (NASA CR-2144) conditions 5, 9 and 10 and at Mach 0.85 between them, the
# identified phugoid period and damping and the speed derivatives X_u, Z_u, M_u (M_u carries the
# sign of Cm_M) must match the small-perturbation model of the same data, and no mode may be
# unstable (jsbsim/tools/jsbsim_speed_modes.py --check). No JSBSim process may be left behind.
set -uo pipefail
TEST_NAME=jsbsim_aircraft
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
FAIL=0
# shellcheck source=test/scripts/lib/jsbsim_mark.sh
source "$ROOT/test/scripts/lib/jsbsim_mark.sh"
MARK=$JSBSIM_MARK
bin=$JSBSIM_BIN
if ! PMRAC_TEST_MARK=$MARK PMRAC_JSBSIM=$bin /usr/bin/python3 "$ROOT/jsbsim/tools/jsbsim_probe.py" linearise --duration 3 --check; then
  echo "FAIL: trim or linearisation of b747_pmrac"
  FAIL=1
fi
if ! PMRAC_TEST_MARK=$MARK PMRAC_JSBSIM=$bin /usr/bin/python3 "$ROOT/jsbsim/tools/jsbsim_speed_modes.py" --check; then
  echo "FAIL: the speed modes of b747_pmrac are not the published data's"
  FAIL=1
fi
left=$(jsbsim_ours)
if [ -n "$left" ]; then
  echo "FAIL: JSBSim processes left behind: $left"
  FAIL=1
fi
if [ "$FAIL" = 0 ]; then echo "$TEST_NAME: PASSED"; else echo "$TEST_NAME: FAILED"; fi
exit "$FAIL"
