# shellcheck shell=bash
# Sourced by the script tests of the batch tools (set TEST_NAME and TOOLS first):
#   TEST_NAME=family_quiet
#   TOOLS="preadapt_family"
#   source "$(dirname "$0")/lib/batch_tools.sh"
# Sets ROOT (the package), BUILD ($PMRAC_BUILD_DIR, default build/) and BIN, the folder of the
# tools: devel/lib/preadaptive_mrac, or the workspace's devel/bin where the last of TOOLS lives
# there instead. Skips (exit 77) when a tool of TOOLS is not built. Makes the scratch folder W
# (removed on exit) and sources counts.sh (ok, bad, finish).
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../../.." && pwd)
BUILD=${PMRAC_BUILD_DIR:-$ROOT/build}
BIN=$BUILD/devel/lib/preadaptive_mrac
last_tool=${TOOLS##* }
[ -x "$BIN/$last_tool" ] || [ ! -x "$BUILD/devel/bin/$last_tool" ] || BIN=$BUILD/devel/bin
for t in $TOOLS; do
  [ -x "$BIN/$t" ] || { echo "SKIPPED: $TEST_NAME: $BIN/$t not built"; exit 77; }
done
W=$(mktemp -d "${TMPDIR:-/tmp}/$TEST_NAME.XXXXXX")
trap 'rm -rf "$W"' EXIT
# shellcheck source=test/scripts/lib/counts.sh
source "$(dirname "${BASH_SOURCE[0]}")/counts.sh"
