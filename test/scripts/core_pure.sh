#!/usr/bin/env bash
# The core library is Eigen + STL: no process, socket or JSBSim code in it (that is the
# preadaptive_mrac_jsbsim library's), and neither the core, the io library nor the core's unit
# tests need the JSBSim library to load. Reads the built libraries with nm and readelf.
set -uo pipefail
TEST_NAME=core_pure
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${PMRAC_BUILD_DIR:-$ROOT/build}
LIB=$BUILD/devel/lib
if [ ! -f "$LIB/libpreadaptive_mrac_core.so" ]; then
  echo "SKIPPED: $TEST_NAME: $LIB/libpreadaptive_mrac_core.so not found (build first)"
  exit 77
fi
FAIL=0
fail() {
  echo "FAIL: $*"
  FAIL=1
}
# Functions only a process or socket owner calls (the C library's names).
SYSCALLS='fork|vfork|execv|execvp|execve|posix_spawn|prctl|socket|connect|bind|listen|accept|waitpid|kill|setsockopt'
for lib in "$LIB/libpreadaptive_mrac_core.so" "$BUILD/libpreadaptive_mrac_core_static.a"; do
  [ -f "$lib" ] || continue
  used=$(nm -C --undefined-only "$lib" 2>/dev/null | awk '{print $NF}' | sed 's/@.*//' |
    grep -xE "$SYSCALLS" | sort -u | tr '\n' ' ')
  [ -z "$used" ] || fail "$(basename "$lib") calls $used(process or socket code in the core)"
  # The engine's code (its parameters, JsbsimParams, are the core's schema).
  jsb=$(nm -C --defined-only "$lib" 2>/dev/null | grep -cE 'Jsbsim(Plant|Process|Error)|lineariseJsbsim|findJsbsim')
  [ "$jsb" -eq 0 ] || fail "$(basename "$lib") defines $jsb symbols of the JSBSim engine"
done
for bin in "$LIB/libpreadaptive_mrac_core.so" "$LIB/libpreadaptive_mrac_io.so" \
  "$LIB"/preadaptive_mrac/test_closed_loop "$LIB"/preadaptive_mrac/test_plant_engine; do
  [ -e "$bin" ] || continue
  if readelf -d "$bin" | grep -q 'NEEDED.*preadaptive_mrac_jsbsim'; then
    fail "$(basename "$bin") needs the JSBSim library"
  fi
done
[ -f "$LIB/libpreadaptive_mrac_jsbsim.so" ] || fail "no JSBSim library (libpreadaptive_mrac_jsbsim.so)"
if [ "$FAIL" -eq 0 ]; then
  echo "ok: the core links no process, socket or JSBSim code"
fi
exit "$FAIL"
