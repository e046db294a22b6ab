# Sourced by the script tests that run the built nodes (set TEST_NAME first):
#   TEST_NAME=late_controller
#   source "$(dirname "$0")/lib/ros_build.sh"
# Sets ROOT (the package) and BUILD ($PMRAC_BUILD_DIR, default build/), defines
# skip REASON ("SKIPPED: TEST_NAME: REASON", exit 77), sources BUILD/devel/setup.bash and
# skips when the build or roslaunch is missing. Expects `set -u` (it restores it).
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../../.." && pwd)
BUILD=${PMRAC_BUILD_DIR:-$ROOT/build}
skip() {
  echo "SKIPPED: $TEST_NAME: $*"
  exit 77
}
[ -f "$BUILD/devel/setup.bash" ] || skip "$BUILD/devel/setup.bash not found (build first)"
set +u
# shellcheck disable=SC1091
source "$BUILD/devel/setup.bash"
set -u
command -v roslaunch >/dev/null || skip "roslaunch not installed"
