#!/usr/bin/env bash
# docs that stay true. Runs the shell commands of the README (its quick start)
# and of every tutorial (docs/tutorials/*.md), page by page, each page in one bash session from
# the repository root, as a reader would: HOME is a scratch folder (so ~/.ros/bags, ~/my_aircraft
# ... land there), the test's own master on a free port, the build of PMRAC_BUILD_DIR. The
# commands left out are named with their reason (test/scripts/lib/doc_commands.py, SKIPS: the
# demo and the test suite themselves, apt-get, a catkin workspace from a clone, realtime runs
# with windows and what needs them); a skip rule no page uses any more fails the test, so the
# list cannot outlive the docs. Links: test/python/test_docs.py.
set -uo pipefail
TEST_NAME=docs_commands
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$(dirname "$0")/lib/launch_scratch.sh"
HELPER=$ROOT/test/scripts/lib/doc_commands.py
PAGES=("$ROOT/README.md" "$ROOT"/docs/tutorials/*.md)
mkdir -p "$TMP/home"
for page in "${PAGES[@]}"; do
  rel=${page#"$ROOT"/}
  /usr/bin/python3 "$HELPER" "$page" "$BUILD" >"$TMP/page.sh" 2>"$TMP/skips" ||
    { echo "FAIL: $rel: the commands could not be read"; FAIL=1; continue; }
  sed "s#^\# SKIPPED: $ROOT/#SKIPPED: #" "$TMP/skips"
  t0=$(date +%s)
  # A reader's shell: the system python3 first (dynparam's `env python3`), HOME in the scratch folder.
  # A page that hangs (a node waiting for a peer that died) fails after 10 min instead of holding
  # the suite.
  if (cd "$ROOT" && HOME=$TMP/home PATH=/usr/bin:$PATH timeout -k 10 600 bash "$TMP/page.sh") >"$TMP/out" 2>&1; then
    echo "ok: $rel: $(grep -c '^+ ' "$TMP/out") commands ran ($(($(date +%s) - t0)) s)"
  else
    echo "FAIL: $rel: $(grep '^FAILED: ' "$TMP/out" | tail -1)"
    grep '^+ ' "$TMP/out" | tail -1
    tail -15 "$TMP/out"
    FAIL=1
  fi
done
# Every skip rule is still needed by some page.
used=$(/usr/bin/python3 "$HELPER" --used "${PAGES[@]}" 2>/dev/null)
while IFS= read -r pattern; do
  grep -qxF -- "$pattern" <<<"$used" || { echo "FAIL: the skip rule '$pattern' matches no command of the docs"; FAIL=1; }
done < <(/usr/bin/python3 "$HELPER" --patterns)
[ "$FAIL" = 0 ] && echo "$TEST_NAME: PASSED" || echo "$TEST_NAME: FAILED"
exit "$FAIL"
