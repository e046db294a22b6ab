#!/usr/bin/env bash
# scripts/run_demo validates before it touches anything and replaces the
# earlier outputs only when a new run has succeeded. Earlier outputs (stand-ins) in a scratch
# --out folder must come through, byte for byte, a scenario with a key typo, a scenario that is
# neither 1-3 nor a file, and a run the nodes refuse (dt:=-1, which only the launch sees); then
# a short good scenario replaces them with a bag and an analysis that names it.
#   Env: PMRAC_BUILD_DIR (default build).
set -uo pipefail
TEST_NAME=run_demo_keeps_outputs
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
# shellcheck source=test/scripts/lib/launch_scratch.sh
source "$(dirname "$0")/lib/launch_scratch.sh"
OUT=$TMP/demo
mkdir -p "$OUT/pa/bags" "$OUT/pa/analysis"
head -c 4096 /dev/urandom >"$OUT/pa/bags/scenario1_rac_vs_pa_2026-01-01-00-00-00.bag"
echo '{"comparison": "earlier"}' >"$OUT/pa/analysis/metrics.json"
echo 'earlier report' >"$OUT/pa/analysis.txt"
echo '{"completed": true}' >"$OUT/pa/rac_plant.json"
sums() { (cd "$OUT" && find pa -type f | sort | xargs sha256sum); }
BEFORE=$(sums)
demo() { # demo ARGS...: run_demo without building, output in $TMP/log, exit code in RC
  RC=0
  REBUILD=0 BUILD_DIR=$BUILD PMRAC_BUILD_DIR=$BUILD timeout 300 "$ROOT/scripts/run_demo" \
    --out "$OUT" --pa-mode pa "$@" >"$TMP/log" 2>&1 || RC=$?
}
cat >"$TMP/short.yaml" <<'YAML'
scenario:
  name: short
  theta:
    - {until: 1.0, scale: 0.1}
    - {until: 2.0, scale: 1.0}
YAML
sed 's/{until: 1.0/{untill: 1.0/' "$TMP/short.yaml" >"$TMP/typo.yaml"
demo --scenario "$TMP/typo.yaml"
check "key typo: exit 2" [ "$RC" = 2 ]
check "key typo: the typo named" grep -q "scenario.theta.0.untill: unknown key" "$TMP/log"
check "key typo: earlier outputs unchanged" [ "$(sums)" = "$BEFORE" ]
demo --scenario 4
check "scenario 4: exit 2" [ "$RC" = 2 ]
check "scenario 4: earlier outputs unchanged" [ "$(sums)" = "$BEFORE" ]
demo --scenario "$TMP/short.yaml" -- dt:=-1
check "refused by the nodes: exit 2" [ "$RC" = 2 ]
check "refused by the nodes: earlier outputs unchanged" [ "$(sums)" = "$BEFORE" ]
check "refused by the nodes: its log kept in failed_run" [ -f "$OUT/failed_run/pa/roslaunch.log" ]
demo --scenario "$TMP/short.yaml"
check "good run: exit 0" [ "$RC" = 0 ]
check "good run: the earlier bag replaced" [ ! -e "$OUT/pa/bags/scenario1_rac_vs_pa_2026-01-01-00-00-00.bag" ]
BAG=$(ls "$OUT"/pa/bags/short_rac_vs_pa_*.bag 2>/dev/null | head -1)
check "good run: a new bag" [ -n "$BAG" ]
SOURCE=$(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["runs"][0]["source"])' \
  "$OUT/pa/analysis/metrics.json" 2>/dev/null)
check "good run: the analysis names a bag that exists ($SOURCE)" [ -f "$OUT/pa/$SOURCE" ]
check "good run: no staging folder or failed_run left" \
  [ -z "$(find "$OUT" -maxdepth 1 -name '.run_demo.*' -o -maxdepth 1 -name failed_run)" ]
if [ "$FAIL" != 0 ]; then
  echo "--- last run_demo output"
  cat "$TMP/log"
  echo "run_demo_keeps_outputs: FAILED"
  exit 1
fi
echo "run_demo_keeps_outputs: PASSED"
