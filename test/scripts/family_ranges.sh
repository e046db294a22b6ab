#!/usr/bin/env bash
# preadapt_family draws the plant conditions per scenario from ranges LO:HI (delay, servo
# lag, Dryden sigma_w; a Lambda per regime): every scenario within its range, the same for every
# mode, reported in runs.jsonl (drawn_conditions), the scenario files and the summary; the same
# family seed draws the same again; bad ranges refused with exit 2 naming the flag.
#   Env: PMRAC_BUILD_DIR (default build).
set -uo pipefail
TEST_NAME=family_ranges
TOOLS="preadapt_family"
# shellcheck source=test/scripts/lib/batch_tools.sh
source "$(dirname "$0")/lib/batch_tools.sh"

RANGES=(--delay 0:0.04 --time-constant 0.02:0.08 --turbulence 0.5:2 --effectiveness 0.4:1.0)
for d in a b; do
  "$BIN/preadapt_family" --seed 7 --count 4 --segments 6 --modes rac,pa_robust --jobs 2 --json \
    "${RANGES[@]}" --out-dir "$W/$d" >"$W/$d.txt" || bad "family with ranges exited $?"
done
grep -q "^plant conditions: plant.actuator.delay 0:0.04 (per scenario), plant.actuator.time_constant 0.02:0.08 (per scenario), plant.turbulence.sigma_w 0.5:2 (per scenario), effectiveness 0.4:1.0 (per regime, the first segment 1)$" "$W/a.txt" &&
  grep -q "^drawn: plant.actuator.delay in \[" "$W/a.txt" && ok "ranges named in the summary" ||
  bad "summary: $(cat "$W/a.txt")"
drawn() { /usr/bin/python3 -c "import json,sys; [print(json.dumps(json.loads(l)['drawn_conditions']), json.loads(l)['iae']) for l in open(sys.argv[1])]" "$1"; }
cmp -s <(drawn "$W/a/runs.jsonl") <(drawn "$W/b/runs.jsonl") && cmp -s "$W/a.txt" "$W/b.txt" &&
  cmp -s "$W/a/scenario_3.yaml" "$W/b/scenario_3.yaml" &&
  ok "the same family seed draws the same (and runs the same)" || bad "two runs of seed 7 differ"
/usr/bin/python3 - "$W/a" <<'PY' && ok "each scenario within its ranges, the same for every mode, Lambda per regime" || bad "drawn conditions"
import json, sys, yaml
d = sys.argv[1]
runs = [json.loads(l) for l in open(d + '/runs.jsonl')]
assert len(runs) == 8, len(runs)
by = {}
for r in runs:
    by.setdefault(r['scenario'], []).append(r['drawn_conditions'])
delays = set()
for path, ds in by.items():
    assert len(ds) == 2 and ds[0] == ds[1], ds  # rac and pa_robust on the same plant
    c = ds[0]
    assert 0 <= c['plant.actuator.delay'] <= 0.04, c
    assert 0.02 <= c['plant.actuator.time_constant'] <= 0.08, c
    assert 0.5 <= c['plant.turbulence.sigma_w'] <= 2, c
    delays.add(c['plant.actuator.delay'])
    sc = yaml.safe_load(open(path))['scenario']
    eff = [s['value'] for s in sc['effectiveness']]
    assert eff == c['effectiveness'] and eff[0] == 1.0, (eff, c)
    lam = {}
    for seg, v in zip(sc['theta'][1:], eff[1:]):
        assert 0.4 <= v <= 1.0, v
        assert lam.setdefault(tuple(seg['theta']), v) == v, 'a regime with two Lambdas'
assert len(delays) == 4, delays  # drawn per scenario, not one per family
PY
"$BIN/preadapt_family" --seed 7 --count 1 --modes rac --delay 0.02 --out-dir "$W/one" >/dev/null &&
  ! grep -q drawn_conditions "$W/one/runs.jsonl" && ok "one value: nothing drawn, nothing added" ||
  bad "a single --delay reports drawn conditions"

refused() {  # expected text, then the arguments
  local want="$1"
  shift
  "$BIN/preadapt_family" --seed 7 --count 1 --modes rac "$@" >"$W/out" 2>"$W/err"
  [ $? = 2 ] && grep -q -- "$want" "$W/err" && ok "refused: $*" || bad "$*: $(cat "$W/err")"
}
refused "--delay: a range LO:HI needs LO < HI" --delay 0.04:0
refused "--delay: both ends must be in \[0, 3600\]" --delay -0.01:0.02
refused "--time-constant: both ends must be >= 0" --time-constant -1:0.02
refused "--time-constant: expected a finite number" --time-constant 0.02:nan
refused "--turbulence: expected a finite number" --turbulence 0.5:2:3
refused "--effectiveness: both ends must be in (0, 2\]" --effectiveness 0:1
refused "--effectiveness: both ends must be in (0, 2\]" --effectiveness 0.5:2.5

finish "family_ranges"
