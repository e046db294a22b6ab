#!/usr/bin/env bash
# The second aircraft of docs/tutorials/own_aircraft.md ("A second aircraft: the Navion"): runs
# the section's commands verbatim (HOME a scratch folder), then holds the flight to what the
# page promises: pa_learn's attention, with thresholds derived from the model, fires after every
# switch, pa_robust's IAE and peak beat rac's, and pa_robust's decisions stay a handful per
# regime switch, not hundreds.
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
for k, w in enumerate(runs["pa_learn"]["windows"][1:], 1):
    if w["onsets"] < 1:
        fail.append(f"pa_learn: no attention onset after switch {k} (t = {w['t_start']} s)")
for key in ("iae", "peak_abs_e"):
    if not runs["pa_robust"][key] < runs["rac"][key]:
        fail.append(f"pa_robust {key} {runs['pa_robust'][key]} not below rac's {runs['rac'][key]}")
switches = len(runs["rac"]["windows"]) - 1
if count("pa_robust", "decision") > 10 * switches:
    fail.append(f"pa_robust: {count('pa_robust', 'decision')} decisions for {switches} switches")
for f in fail:
    print("FAIL:", f)
print("own_aircraft_navion:", "FAILED" if fail else "PASSED")
sys.exit(1 if fail else 0)
PY
