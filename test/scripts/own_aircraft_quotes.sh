#!/usr/bin/env bash
# docs/tutorials/own_aircraft.md, sections 1 and 2: every peak the page quotes ("peak |e| X rad
# for MODE") is one its commands fly, and is what they fly. Section 1's commands run verbatim
# (HOME a scratch folder); each quoted mode must have a `--mode MODE` line in section 2, and
# its run (the same files, --json) must give the quoted peak to the digits quoted (within 5 %).
set -uo pipefail
TEST_NAME=own_aircraft_quotes
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${PMRAC_BUILD_DIR:-$ROOT/build}
SIM=$BUILD/devel/bin/preadapt_sim
[ -x "$SIM" ] || { echo "SKIPPED: $TEST_NAME: build preadapt_sim first"; exit 77; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
SIM=$SIM /usr/bin/python3 - "$ROOT/docs/tutorials/own_aircraft.md" "$TMP" <<'PY'
import json
import os
import re
import subprocess
import sys

page, tmp = sys.argv[1], sys.argv[2]
text = open(page).read()


def section(title):
    start = text.find(title)
    if start < 0:
        sys.exit(f"FAIL: no section '{title}'")
    end = text.find("\n## ", start + 1)
    return text[start : end if end > 0 else len(text)]


setup = re.findall(r"```sh\n(.*?)```", section("## 1. "), re.S)
fly = section("## 2. ")
home = os.path.join(tmp, "home")
os.makedirs(home)
env = dict(os.environ, HOME=home)
subprocess.run(["bash", "-e", "-c", setup[0]], env=env, check=True, cwd=tmp)
folder = os.path.join(home, "my_aircraft")
quoted = re.findall(r"([0-9.]+)\s+rad\s+for\s+(\w+)", re.sub(r"\s+", " ", fly))
if not quoted:
    sys.exit("FAIL: section 2 quotes no peak")
fail = []
for value, mode in quoted:
    if f"--mode {mode}" not in fly:
        fail.append(f"{mode}: quoted ({value} rad) but no command of section 2 flies it")
        continue
    run = subprocess.run(
        [os.environ["SIM"], "--plant", "plant.yaml", "--controller",
         "controller.yaml", "--scenario", "scenario.yaml", "--mode", mode, "--json"],
        cwd=folder, capture_output=True, text=True, check=True)
    peak = json.loads(run.stdout.strip().splitlines()[-1])["peak_abs_e"]
    ok = abs(peak - float(value)) <= 0.05 * float(value)
    print(f"{'ok' if ok else 'FAIL'}: {mode} peak |e| {peak:.4g} rad, the page says {value}")
    if not ok:
        fail.append(f"{mode}: the page says {value} rad, its run gives {peak:.4g}")
for f in fail:
    print("FAIL:", f)
sys.exit(1 if fail else 0)
PY
rc=$?
if [ "$rc" = 0 ]; then echo "$TEST_NAME: PASSED"; else echo "$TEST_NAME: FAILED"; fi
exit "$rc"
