#!/usr/bin/env bash
# preadapt_family runs a failed run once more. A JSBSim process that stops answering (here
# SIGSTOPped, as a process starved on a loaded machine) costs that run, not the family: the
# family names the run and the cause, ends with exit 0, and its summary and runs equal an
# undisturbed family's. A run that fails twice ends the family with exit 1, naming the
# scenario, the mode and the cause. No JSBSim is left behind either way.
#   Env: PMRAC_BUILD_DIR (default build); JSBSim from scripts/install_jsbsim.
set -uo pipefail
TEST_NAME=family_jsbsim_retry
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
BUILD=${PMRAC_BUILD_DIR:-$ROOT/build}
# shellcheck source=test/scripts/lib/jsbsim_mark.sh
source "$ROOT/test/scripts/lib/jsbsim_mark.sh"
[ -x "$BUILD/devel/bin/preadapt_family" ] || { echo "SKIPPED: $TEST_NAME: build preadapt_family first"; exit 77; }
# Every JSBSim started here carries the mark (jsbsim_ours lists them).
export PMRAC_JSBSIM=$JSBSIM_BIN PMRAC_TEST_MARK=$JSBSIM_MARK
W=$(mktemp -d "${TMPDIR:-/tmp}/$TEST_NAME.XXXXXX")
trap 'rm -rf "$W"' EXIT
# shellcheck source=test/scripts/lib/counts.sh
source "$ROOT/test/scripts/lib/counts.sh"

# One scenario of two segments, rac only: one JSBSim run of about 40 s of flight. A JSBSim
# that does not answer for 2 s ends its run.
F=("$BUILD/devel/bin/preadapt_family" --seed 5 --count 1 --regimes 1 --segments 2 --modes rac --jobs 1
  --set plant.engine=jsbsim --set plant.jsbsim.timeout=2 --json)

# SIGSTOP the first $2 JSBSim children of process $1 (each once it runs), then wait for $1.
# STOPPED: the pids stopped, over every call.
STOPPED=""
stop_jsbsim() {
  local fam=$1 left=$2 seen="" p
  while kill -0 "$fam" 2>/dev/null && [ "$left" -gt 0 ]; do
    for p in $(pgrep -P "$fam" -x JSBSim); do
      case " $seen " in *" $p "*) continue ;; esac
      sleep 0.3 # into its run
      kill -STOP "$p" 2>/dev/null && seen="$seen $p" && left=$((left - 1)) && STOPPED="$STOPPED $p"
    done
    sleep 0.05
  done
  wait "$fam"
}
# runs.jsonl without what differs by itself: the wall time, the --out-dir in the scenario path
runs_of() {
  /usr/bin/python3 -c 'import json, os, sys
for l in open(sys.argv[1]):
    d = json.loads(l)
    d.pop("wall_time_s", None)
    d["scenario"] = os.path.basename(d["scenario"])
    print(json.dumps(d, sort_keys=True))' "$1"
}

"${F[@]}" --out-dir "$W/ref" >"$W/ref.txt" 2>"$W/ref.err" ||
  bad "undisturbed family exited $?: $(tail -3 "$W/ref.err")"

"${F[@]}" --out-dir "$W/once" >"$W/once.txt" 2>"$W/once.err" &
fam=$!
stop_jsbsim "$fam" 1
rc=$?
[ "$rc" = 0 ] && ok "a JSBSim stopped once: the family ends with exit 0" ||
  bad "a JSBSim stopped once: exit $rc: $(tail -3 "$W/once.err")"
grep -q "^preadapt_family: scenario 0, mode rac: .*JSBSim did not answer within.*(it was still running (state T, [0-9.]* s of CPU), killed now).*; running it once more$" \
  "$W/once.err" && ok "the failed run is named with its cause and JSBSim's state (stopped), and run once more" ||
  bad "stderr: $(cat "$W/once.err")"
[ -s "$W/ref/runs.jsonl" ] && cmp -s "$W/ref.txt" "$W/once.txt" &&
  cmp -s <(runs_of "$W/ref/runs.jsonl") <(runs_of "$W/once/runs.jsonl") &&
  ok "the summary and runs.jsonl equal the undisturbed family's" ||
  bad "the family differs: $(diff "$W/ref.txt" "$W/once.txt" | head -5)"

"${F[@]}" --out-dir "$W/twice" >"$W/twice.txt" 2>"$W/twice.err" &
fam=$!
stop_jsbsim "$fam" 2
rc=$?
[ "$rc" = 1 ] && grep -q "^preadapt_family: error: scenario 0, mode rac: .*JSBSim did not answer within" \
  "$W/twice.err" && ok "a run that fails twice: exit 1, naming the scenario, the mode and the cause" ||
  bad "failed twice: exit $rc: $(cat "$W/twice.err")"
[ ! -s "$W/twice/runs.jsonl" ] && ok "no runs.jsonl for a family that did not end" ||
  bad "runs.jsonl written for a failed family"
sleep 0.5
# shellcheck disable=SC2086
[ "$(echo $STOPPED | wc -w)" = 3 ] && [ -z "$(jsbsim_ours)" ] && ok "no JSBSim left behind (3 stopped)" ||
  bad "stopped JSBSim processes:$STOPPED; this test's left: $(jsbsim_ours)"
finish family_jsbsim_retry
