# shellcheck shell=bash
# For a JSBSim script test: the JSBSim binary (scripts/install_jsbsim) as $JSBSIM_BIN, and this
# run's mark, which every JSBSim the test starts inherits in its environment (PMRAC_TEST_MARK),
# so `jsbsim_ours` lists this test's JSBSim processes and not those of other runs on the machine.
# Source it after setting ROOT and TEST_NAME; it exits the test when there is no binary.
JSBSIM_MARK="${TEST_NAME}_$$_$(date +%s%N)"
jsbsim_ours() {
  local p
  for p in $(pgrep -x JSBSim); do
    tr '\0' '\n' <"/proc/$p/environ" 2>/dev/null | grep -qxF "PMRAC_TEST_MARK=$JSBSIM_MARK" && echo "$p"
  done
}
if ! JSBSIM_BIN=$("$ROOT/scripts/install_jsbsim" | tail -n1) || [ ! -x "$JSBSIM_BIN" ]; then
  echo "FAIL: scripts/install_jsbsim did not give a JSBSim binary"
  echo "$TEST_NAME: FAILED"
  exit 1
fi
