#!/usr/bin/env bash
# preadapt_family with the noise through --set plant.noise.std: the summary names that noise
# (not "noise 0"), every scenario gets a noise seed of its own (the same for every mode), and
# every line of runs.jsonl has a real wall_time_s. Also: scenario.launch names a JSBSim bag
# apart from a linear one (roslaunch --dump-params, no master).  Env: PMRAC_BUILD_DIR.
set -uo pipefail
TEST_NAME=family_noise_wall
TOOLS="preadapt_family"
# shellcheck source=test/scripts/lib/batch_tools.sh
source "$(dirname "$0")/lib/batch_tools.sh"

"$BIN/preadapt_family" --seed 7 --count 3 --segments 6 --modes rac,pa_learn --jobs 2 \
  --set 'plant.noise.std=[0,0.001,0.001]' --out-dir "$W/a" >"$W/a.txt" || bad "family exited $?"
grep -q "noise std \[0, 0.001, 0.001\]" "$W/a.txt" && ok "the --set noise named in the summary" ||
  bad "summary: $(head -1 "$W/a.txt")"
/usr/bin/python3 - "$W/a/runs.jsonl" <<'PY' && ok "a noise seed per scenario, real wall_time_s" || bad "runs.jsonl"
import json, sys
runs = [json.loads(l) for l in open(sys.argv[1])]
assert len(runs) == 6, len(runs)
assert all(r['wall_time_s'] > 0.0 for r in runs), [r['wall_time_s'] for r in runs]
seeds = {}
for r in runs:
    seeds.setdefault(r['scenario'], set()).add(r['noise_seed'])
assert all(len(s) == 1 for s in seeds.values()), seeds  # the same for every mode
assert len({next(iter(s)) for s in seeds.values()}) == 3, seeds  # its own per scenario
PY

if command -v roslaunch >/dev/null; then
  dump() { ROS_PACKAGE_PATH="$ROOT:${ROS_PACKAGE_PATH:-}" roslaunch --dump-params \
    "$ROOT/launch/scenario.launch" record:=true guard:=false "$@" 2>&1 | grep output_prefix; }
  j=$(dump plant_engine:=jsbsim)
  l=$(dump)
  [[ $j == *"/scenario1_jsbsim_pa_learn" && $l == *"/scenario1_pa_learn" ]] &&
    ok "a JSBSim bag named apart from a linear one" || bad "bag prefixes: '$j' '$l'"
fi
finish "family_noise_wall"
