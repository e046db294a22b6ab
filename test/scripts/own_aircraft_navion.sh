#!/usr/bin/env bash
# The second aircraft of docs/tutorials/own_aircraft.md ("A second aircraft: the Navion"): runs
# the section's commands verbatim (HOME a scratch folder), then holds the flight to what the
# page promises: pa_learn's attention fires, pa_robust's IAE beats rac's, and pa_robust's
# decisions stay a handful per regime switch, not hundreds.
set -uo pipefail
TEST_NAME=own_aircraft_navion
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${PMRAC_BUILD_DIR:-$ROOT/build}
[ -f "$BUILD/devel/setup.bash" ] || { echo "SKIPPED: $TEST_NAME: build first"; exit 77; }
set +u
# shellcheck disable=SC1091
source "$BUILD/devel/setup.bash"
set -u
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
PAGE=$ROOT/docs/tutorials/own_aircraft.md
/usr/bin/python3 - "$PAGE" >"$TMP/run.sh" <<'PY' || { echo "$TEST_NAME: FAILED (no Navion section)"; exit 1; }
import re
import sys

text = open(sys.argv[1]).read()
start = text.find("## 4. A second aircraft: the Navion")
if start < 0:
    sys.exit(1)
end = text.find("\n## ", start + 1)
section = text[start : end if end > 0 else len(text)]
blocks = re.findall(r"```sh\n(.*?)```", section, re.S)
if not blocks:
    sys.exit(1)
print("\n".join(blocks))
PY
if ! (cd "$ROOT" && HOME=$TMP PATH=/usr/bin:$PATH bash -e "$TMP/run.sh") >"$TMP/out" 2>&1; then
  tail -15 "$TMP/out"
  echo "$TEST_NAME: FAILED (the section's commands)"
  exit 1
fi
cat "$TMP/out"
/usr/bin/python3 - "$TMP/navion" <<'PY'
import json
import sys

runs = {}
for mode in ("rac", "pa_learn", "pa_robust"):
    with open(f"{sys.argv[1]}/{mode}.json") as f:
        runs[mode] = json.loads(f.read().strip().splitlines()[-1])


def count(mode, kind):
    return sum(e["type"] == kind for e in runs[mode]["events"])


fail = []
if count("pa_learn", "onset") < 1:
    fail.append("pa_learn: no attention onset")
if not runs["pa_robust"]["iae"] < runs["rac"]["iae"]:
    fail.append(f"pa_robust IAE {runs['pa_robust']['iae']} not below rac's {runs['rac']['iae']}")
switches = len(runs["rac"]["windows"]) - 1
if count("pa_robust", "decision") > 10 * switches:
    fail.append(f"pa_robust: {count('pa_robust', 'decision')} decisions for {switches} switches")
if runs["pa_learn"]["iae"] > 1.5 * runs["rac"]["iae"]:
    fail.append(f"pa_learn IAE {runs['pa_learn']['iae']} above 1.5 x rac's {runs['rac']['iae']}")
for f in fail:
    print("FAIL:", f)
print("own_aircraft_navion:", "FAILED" if fail else "PASSED")
sys.exit(1 if fail else 0)
PY
