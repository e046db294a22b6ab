#!/usr/bin/env bash
# preadapt_family under sensor noise: a switch window where rac's peak |e| is within twice the
# noise's largest excursion is quiet, named in the summary and runs.jsonl, and judged by no
# ratio. Checked against the rule recomputed from runs.jsonl (each window's length and rac's
# peak), the judged worst and revisit ratios against the windows left, and --quiet-factor 0
# (every window judged) against the same runs. Env: PMRAC_BUILD_DIR.
set -uo pipefail
TEST_NAME=family_quiet
TOOLS="preadapt_family"
# shellcheck source=test/scripts/lib/batch_tools.sh
source "$(dirname "$0")/lib/batch_tools.sh"

# Seed 55 holds three quiet windows at 0.1 mrad (a development family).
# shellcheck disable=SC2054  # --modes takes a comma list
args=(--seed 55 --count 30 --segments 8 --noise 1e-4 --time-constant 0.05
  --modes rac,pa_robust,oracle --jobs 2 --json)
"$BIN/preadapt_family" "${args[@]}" --out-dir "$W/a" >"$W/a.txt" || bad "family exited $?"
"$BIN/preadapt_family" "${args[@]}" --quiet-factor 0 --out-dir "$W/b" >"$W/b.txt" ||
  bad "family --quiet-factor 0 exited $?"
grep -q "^quiet windows: [1-9][0-9]* of the [0-9]*, not judged" "$W/a.txt" &&
  ok "the summary names the quiet windows" || bad "summary: $(head -3 "$W/a.txt")"
grep -q "^quiet windows" "$W/b.txt" && bad "--quiet-factor 0 still names quiet windows" ||
  ok "--quiet-factor 0: none"
/usr/bin/python3 - "$W" <<'PY' && ok "quiet windows as the rule says, left out of every ratio" ||
import json, math, sys
w = sys.argv[1]


def load(d):
    runs = {}
    for line in open('%s/%s/runs.jsonl' % (w, d)):
        r = json.loads(line)
        runs.setdefault(r['scenario'].split('/')[-1], {})[r['mode']] = r
    lines = {}
    for line in open('%s/%s.txt' % (w, d)):
        if line.startswith('{'):
            j = json.loads(line)
            lines[j['mode']] = j
    return runs, lines


runs, lines = load('a')
_, every = load('b')
quiet_seen = 0
pa, orc, rev = [], [], []
for sc, m in runs.items():
    rac = m['rac']
    for w_, q in zip(rac['revisits']['windows'], rac['revisits']['quiet']):
        win = rac['windows'][w_]
        n = (win['t_end'] - win['t_start']) / rac['dt']
        rule = win['peak_abs_e'] <= 2.0 * 1e-4 * math.sqrt(2.0 * math.log(2.0 * n))
        assert q == rule, (sc, w_, q, rule)
        for mode in ('pa_robust', 'oracle'):
            assert m[mode]['revisits']['quiet'] == rac['revisits']['quiet'], (sc, mode)
        if q:
            quiet_seen += 1
            continue
        pa.append(m['pa_robust']['windows'][w_]['peak_abs_e'] / win['peak_abs_e'])
        orc.append(m['oracle']['windows'][w_]['peak_abs_e'] / win['peak_abs_e'])
        rev.append(m['pa_robust']['windows'][w_]['peak_abs_e'] /
                   m['oracle']['windows'][w_]['peak_abs_e'])
assert quiet_seen > 0
p = lines['pa_robust']
assert p['quiet_windows'] == quiet_seen and p['quiet_factor'] == 2.0, p['quiet_windows']
assert p['windows'] == len(pa), (p['windows'], len(pa))
assert abs(p['worst_ratio'] - max(pa)) < 1e-12, (p['worst_ratio'], max(pa))
assert abs(lines['oracle']['worst_ratio'] - max(orc)) < 1e-12
assert p['revisits']['count'] == len(rev)
assert abs(p['revisits']['worst'] - max(rev)) < 1e-12
e = every['pa_robust']
assert e['quiet_windows'] == 0 and e['windows'] == len(pa) + quiet_seen, e['windows']
PY
  bad "quiet windows"
"$BIN/preadapt_family" --seed 1 --count 1 --quiet-factor -1 >/dev/null 2>"$W/err.txt"
[ $? -eq 2 ] && grep -q "quiet-factor" "$W/err.txt" && ok "a bad --quiet-factor refused, named" ||
  bad "--quiet-factor -1: $(cat "$W/err.txt")"
finish "family_quiet"
