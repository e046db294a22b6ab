#!/usr/bin/env bash
# preadapt_sweep --shard K/N and --merge. The same sweep (2 modes x 2 seeds x a
# 3-value grid = 12 runs) unsharded, then sharded 1, 3 and 5 ways (5 > some slices' share:
# uneven slices) run by GNU parallel with the command line of docs/reference/sweeps.md, merged: each
# merge must be byte-identical to the unsharded output. Then what the merge must refuse
# (a shard missing, a shard twice, a cut-short shard, another sweep's shard) and what
# --shard must refuse (exit 2, one line).
#   Env: PMRAC_BUILD_DIR (default build).
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${PMRAC_BUILD_DIR:-$ROOT/build}
SWEEP=$BUILD/devel/lib/preadaptive_mrac/preadapt_sweep
[ -x "$SWEEP" ] || { echo "SKIPPED: sweep_shards: $SWEEP not built"; exit 77; }
command -v parallel >/dev/null ||
  { echo "SKIPPED: sweep_shards: GNU parallel not installed (apt-get install parallel)"; exit 77; }
W=$(mktemp -d "${TMPDIR:-/tmp}/sweep_shards.XXXXXX")
trap 'rm -rf "$W"' EXIT
# shellcheck source=test/scripts/lib/counts.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib/counts.sh"

ARGS=(--scenario 1 --modes rac,pa_learn --seeds 1-2
  --grid controller.attention.c_ed=0.015,0.02,0.03 --no-wall-time --jobs 1)
"$SWEEP" "${ARGS[@]}" >"$W/all.jsonl" || bad "unsharded sweep exited $?"
[ "$(wc -l <"$W/all.jsonl")" = 12 ] && ok "unsharded: 12 lines" ||
  bad "unsharded: $(wc -l <"$W/all.jsonl") lines, expected 12"

for N in 1 3 5; do
  mkdir -p "$W/$N"
  # The documented command line: one process per shard, shard K's output in shard_K.jsonl.
  parallel --will-cite --halt now,fail=1 -j 2 \
    "$SWEEP" "${ARGS[@]}" --shard "{}/$N" ">" "$W/$N/shard_{}.jsonl" ::: $(seq 0 $((N - 1)))
  rc=$?
  [ "$rc" = 0 ] || { bad "$N shards: parallel exited $rc"; continue; }
  total=$(cat "$W/$N"/shard_*.jsonl | wc -l)
  [ "$total" = 12 ] && ok "$N shards: 12 lines in all" || bad "$N shards: $total lines in all"
  # Disjoint: every index once across the shards.
  dup=$(cat "$W/$N"/shard_*.jsonl | sed 's/^{"index":\([0-9]*\),.*/\1/' | sort -n | uniq -d)
  [ -z "$dup" ] && ok "$N shards: disjoint" || bad "$N shards: indices in two shards: $dup"
  # Any order of the files.
  mapfile -t files < <(ls "$W/$N"/shard_*.jsonl | sort -r)
  if "$SWEEP" "${ARGS[@]}" --merge "${files[@]}" >"$W/$N/merged.jsonl" 2>"$W/$N/err"; then
    cmp -s "$W/all.jsonl" "$W/$N/merged.jsonl" && ok "$N shards: merge == unsharded (cmp)" ||
      bad "$N shards: merge differs from the unsharded sweep"
  else
    bad "$N shards: merge failed: $(cat "$W/$N/err")"
  fi
done

# Without --no-wall-time the lines differ only in wall_time_s: the merge keeps every run.
TIMED=(--scenario 1 --modes rac,pa_learn --seeds 1-2
  --grid controller.attention.c_ed=0.015,0.02,0.03 --jobs 1)
"$SWEEP" "${TIMED[@]}" --shard 0/2 >"$W/t0.jsonl" &&
  "$SWEEP" "${TIMED[@]}" --shard 1/2 >"$W/t1.jsonl" &&
  "$SWEEP" "${TIMED[@]}" --merge "$W/t1.jsonl" "$W/t0.jsonl" >"$W/t.jsonl"
if [ "$(grep -c '"wall_time_s":' "$W/t.jsonl")" = 12 ] &&
  [ "$(sed 's/,"wall_time_s":[^,}]*//' "$W/t.jsonl")" = "$(cat "$W/all.jsonl")" ]; then
  ok "with wall_time_s: merge == unsharded but for wall_time_s"
else
  bad "with wall_time_s: merge differs from the unsharded sweep beyond wall_time_s"
fi

# refuse NAME EXPECTED_RC PATTERN CMD...: exit code and a one-line error matching PATTERN.
refuse() {
  local name=$1 want=$2 pattern=$3 rc
  shift 3
  "$@" >"$W/out" 2>"$W/err"
  rc=$?
  if [ "$rc" != "$want" ]; then
    bad "$name: exit code $rc, expected $want ($(head -c 300 "$W/err"))"
  elif [ "$(wc -l <"$W/err")" != 1 ] || ! grep -qE -- "$pattern" "$W/err"; then
    bad "$name: stderr is not one line matching /$pattern/: $(cat "$W/err")"
  elif [ -s "$W/out" ]; then
    bad "$name: printed output on failure"
  else
    ok "$name: exit $want, $(cat "$W/err")"
  fi
}
S=$W/3
refuse "merge: a shard missing" 1 "run 1 of 12 is in none" \
  "$SWEEP" "${ARGS[@]}" --merge "$S/shard_0.jsonl" "$S/shard_2.jsonl"
refuse "merge: a shard twice" 1 "shard_1.jsonl:1: run 1 again" \
  "$SWEEP" "${ARGS[@]}" --merge "$S/shard_0.jsonl" "$S/shard_1.jsonl" "$S/shard_1.jsonl" \
  "$S/shard_2.jsonl"
head -c 200 "$S/shard_1.jsonl" >"$W/cut.jsonl"
refuse "merge: a shard cut short" 1 "cut.jsonl:1: not a JSON line" \
  "$SWEEP" "${ARGS[@]}" --merge "$S/shard_0.jsonl" "$W/cut.jsonl" "$S/shard_2.jsonl"
refuse "merge: another sweep's shards" 1 "another mode, seed or grid" \
  "$SWEEP" --scenario 1 --modes rac,pa_learn --seeds 3-4 \
  --grid controller.attention.c_ed=0.015,0.02,0.03 --merge "$S"/shard_*.jsonl
refuse "merge: a file that is not there" 1 "nope.jsonl: cannot open" \
  "$SWEEP" "${ARGS[@]}" --merge "$W/nope.jsonl"
refuse "--shard 3/3" 2 "--shard '3/3': K must be in 0..2 \(K is 0-based\)" \
  "$SWEEP" "${ARGS[@]}" --shard 3/3
refuse "--shard 1/0" 2 "--shard '1/0': N must be >= 1" "$SWEEP" "${ARGS[@]}" --shard 1/0
refuse "--shard 2" 2 "--shard '2': expected K/N" "$SWEEP" "${ARGS[@]}" --shard 2
refuse "--shard a/3" 2 "--shard" "$SWEEP" "${ARGS[@]}" --shard a/3
refuse "--shard with --merge" 2 "give one of them" \
  "$SWEEP" "${ARGS[@]}" --shard 0/3 --merge "$S/shard_0.jsonl"

finish "sweep_shards"
