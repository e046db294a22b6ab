#!/usr/bin/env bash
# Benchmarks of the package, in one run: builds in its own directory, runs the Google Benchmark
# (Controller::step per mode, full scenario 3 per mode) with repetitions, times the batch CLI
# against the Python/numpy prototype on the same work (scenario 1, rac), optionally counts
# instructions with callgrind, and writes the table to docs/performance.md.
#
# Not a test: it passes or fails nothing; it reports medians.
#
# Environment (all optional):
#   BUILD_DIR=build_bench   build directory (Release)
#   REPS=10                 Google Benchmark repetitions (medians are reported)
#   PY_RUNS=5               runs of each command in the CLI-vs-prototype timing
#   JOBS=2                  parallel compile jobs
#   CALLGRIND=auto          1: count instructions with valgrind, 0: skip, auto: when installed
#   BASELINE_BUILD=         a build directory of another commit (preadapt_sim built there, e.g.
#                           a git worktree at the base of a change): its CLI runs scenario 3 in
#                           every mode interleaved with this build's, its outputs are compared
#                           byte for byte, and (with callgrind) its instructions counted too
#   BASE_RUNS=$PY_RUNS      runs of each build per mode against the baseline
#   OUT=docs/performance.md (its sections the report does not write are kept)
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
BUILD_DIR="${BUILD_DIR:-build_bench}"
REPS="${REPS:-10}"
PY_RUNS="${PY_RUNS:-5}"
JOBS="${JOBS:-2}"
CALLGRIND="${CALLGRIND:-auto}"
OUT="${OUT:-docs/performance.md}"
BASELINE_BUILD="${BASELINE_BUILD:-}"
BASE_RUNS="${BASE_RUNS:-$PY_RUNS}"
PY=/usr/bin/python3
RES="$BUILD_DIR/bench_results"

log() { printf '\n== %s\n' "$*"; }

LOAD_BEFORE="$(cut -d' ' -f1-3 /proc/loadavg)"

log "configure and build ($BUILD_DIR, Release)"
CONFIGURE=(cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3)
BUILD=(cmake --build "$BUILD_DIR" --target bench_controller preadapt_sim -j"$JOBS")
mkdir -p "$BUILD_DIR"
"${CONFIGURE[@]}" >"$BUILD_DIR/configure.log" 2>&1 || { cat "$BUILD_DIR/configure.log"; exit 1; }
"${BUILD[@]}"
BIN="$BUILD_DIR/devel/lib/preadaptive_mrac"
SIM="$BIN/preadapt_sim"
BENCH="$BIN/bench_controller"
[[ -x "$SIM" && -x "$BENCH" ]] || { echo "run_bench: $SIM or $BENCH not built" >&2; exit 1; }
# every mode of params/modes.yaml, as the build registers them
mapfile -t MODES < <("$SIM" --list-modes | cut -f1)
BASE_SIM=""
# whether the baseline has mode $1 (an older build refuses a newer mode by name)
base_has() { [[ -n "$BASE_SIM" ]] && "$BASE_SIM" --scenario 3 --mode "$1" --json >/dev/null 2>&1; }
if [[ -n "$BASELINE_BUILD" ]]; then
  BASE_SIM="$BASELINE_BUILD/devel/lib/preadaptive_mrac/preadapt_sim"
  [[ -x "$BASE_SIM" ]] || { echo "run_bench: $BASE_SIM not built" >&2; exit 1; }
fi
rm -rf "$RES"
mkdir -p "$RES"

log "Google Benchmark ($REPS repetitions, medians)"
BENCH_CMD=("$BENCH" --benchmark_repetitions="$REPS" --benchmark_report_aggregates_only=true
           --benchmark_out="$RES/bench.json" --benchmark_out_format=json)
"${BENCH_CMD[@]}"

log "cross-check: prototype against the CLI (scenario 1, rac)"
CLI_CMD=("$SIM" --scenario 1 --mode rac --json)
PROTO_CMD=("$PY" bench/prototype_rac.py --quiet)
# With a baseline build, its CLI is a third command of the same runs (the ratio before).
BASE_CLI_CMD=()
[[ -n "$BASE_SIM" ]] && BASE_CLI_CMD=("$BASE_SIM" --scenario 1 --mode rac --json)
"${CLI_CMD[@]}" >"$RES/cli_s1_rac.json"
"$PY" bench/prototype_rac.py --cli-json "$RES/cli_s1_rac.json" | tee "$RES/prototype_xcheck.txt" |
  grep -v '^{'

HYPERFINE_CMD=""
if command -v hyperfine >/dev/null 2>&1; then
  log "hyperfine: CLI vs prototype ($PY_RUNS runs each)"
  HF=(hyperfine -N --warmup 1 --runs "$PY_RUNS" --export-json "$RES/hyperfine.json"
      "${CLI_CMD[*]}" "${PROTO_CMD[*]}")
  [[ -n "$BASE_SIM" ]] && HF+=("${BASE_CLI_CMD[*]}")
  "${HF[@]}"
  HYPERFINE_CMD="hyperfine -N --warmup 1 --runs $PY_RUNS --export-json $RES/hyperfine.json '${CLI_CMD[*]}' '${PROTO_CMD[*]}'${BASE_SIM:+ '${BASE_CLI_CMD[*]}'}"
else
  echo "hyperfine not installed (apt-get install -y hyperfine): using the timing loop only"
fi

log "interleaved timing loop: CLI vs prototype ($PY_RUNS runs each)"
LOOP_CMD=("$PY" bench/perf_report.py timeloop --reps "$PY_RUNS" --out "$RES/timeloop.json" --
          "${CLI_CMD[@]}" ::: "${PROTO_CMD[@]}")
[[ -n "$BASE_SIM" ]] && LOOP_CMD+=(::: "${BASE_CLI_CMD[@]}")
"${LOOP_CMD[@]}"

BASE_CMD=""
BASE_CG_CMD=""
if [[ -n "$BASE_SIM" ]]; then
  BASE_COMMIT="$(git -C "$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$BASELINE_BUILD/CMakeCache.txt")" \
                 rev-parse --short HEAD 2>/dev/null || echo unknown)"
  log "against the baseline build $BASELINE_BUILD (commit $BASE_COMMIT): scenario 3, every mode"
  BASE_LOAD_BEFORE="$(cut -d' ' -f1-3 /proc/loadavg)"
  IDENTICAL=""
  strip_wall() { sed -E 's/"wall_time_s":[0-9.eE+-]+//'; }
  for m in "${MODES[@]}"; do
    if ! base_has "$m"; then echo "  $m: not in the baseline"; continue; fi
    "$SIM" --scenario 3 --mode "$m" --json --csv "$RES/same.new.csv" | strip_wall >"$RES/same.new.json"
    "$BASE_SIM" --scenario 3 --mode "$m" --json --csv "$RES/same.base.csv" | strip_wall >"$RES/same.base.json"
    if cmp -s "$RES/same.new.json" "$RES/same.base.json" && cmp -s "$RES/same.new.csv" "$RES/same.base.csv"; then
      same=1
    else
      same=0
    fi
    echo "  $m: same bytes: $same"
    IDENTICAL="${IDENTICAL:+$IDENTICAL,}$m=$same"
    "$PY" bench/perf_report.py timeloop --reps "$BASE_RUNS" --out "$RES/timeloop_base.$m.json" -- \
      "$SIM" --scenario 3 --mode "$m" --json ::: "$BASE_SIM" --scenario 3 --mode "$m" --json
  done
  rm -f "$RES"/same.*
  BASE_CMD="for each mode: $PY bench/perf_report.py timeloop --reps $BASE_RUNS --out $RES/timeloop_base.<mode>.json -- $SIM --scenario 3 --mode <mode> --json ::: $BASE_SIM --scenario 3 --mode <mode> --json"
fi

CG_CMD=""
if [[ "$CALLGRIND" == 1 || ( "$CALLGRIND" == auto && -x "$(command -v valgrind || true)" ) ]]; then
  log "callgrind: instructions per sample, scenario 3"
  for m in "${MODES[@]}"; do
    valgrind --tool=callgrind --callgrind-out-file="$RES/callgrind.$m.out" \
      "$SIM" --scenario 3 --mode "$m" --json >/dev/null 2>"$RES/callgrind.$m.log"
    callgrind_annotate --inclusive=yes "$RES/callgrind.$m.out" >"$RES/callgrind.$m.txt" 2>/dev/null
    callgrind_annotate "$RES/callgrind.$m.out" >"$RES/callgrind.$m.excl.txt" 2>/dev/null
    "$PY" bench/perf_report.py callgrind --out "$RES/callgrind.json" --mode "$m" \
      --ir-file "$RES/callgrind.$m.txt" --excl-file "$RES/callgrind.$m.excl.txt"
    if base_has "$m"; then
      valgrind --tool=callgrind --callgrind-out-file="$RES/callgrind_base.$m.out" \
        "$BASE_SIM" --scenario 3 --mode "$m" --json >/dev/null 2>"$RES/callgrind_base.$m.log"
      callgrind_annotate --inclusive=yes "$RES/callgrind_base.$m.out" >"$RES/callgrind_base.$m.txt" 2>/dev/null
      "$PY" bench/perf_report.py callgrind --out "$RES/callgrind_base.json" --mode "$m" \
        --ir-file "$RES/callgrind_base.$m.txt"
    fi
    echo "  $m done"
  done
  CG_CMD="valgrind --tool=callgrind --callgrind-out-file=$RES/callgrind.<mode>.out $SIM --scenario 3 --mode <mode> --json; callgrind_annotate --inclusive=yes $RES/callgrind.<mode>.out"
  [[ -n "$BASE_SIM" ]] && BASE_CG_CMD="the same with $BASE_SIM (callgrind_base.<mode>.*)"
fi

LOAD_AFTER="$(cut -d' ' -f1-3 /proc/loadavg)"
if [[ -n "$BASE_SIM" ]]; then
  "$PY" bench/perf_report.py baseline --out "$RES/baseline.json" --commit "$BASE_COMMIT" \
    --build-dir "$BASELINE_BUILD" --reps "$BASE_RUNS" --load "$BASE_LOAD_BEFORE / $LOAD_AFTER" \
    --identical "$IDENTICAL" -- "$RES"/timeloop_base.*.json
fi

log "report"
CXX="$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$BUILD_DIR/CMakeCache.txt")"
export META_DATE="$(date -u '+%Y-%m-%d %H:%M UTC')"
export META_CPU="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
export META_NPROC="$(nproc)"
export META_KERNEL="Linux $(uname -r)"
export META_LOAD_BEFORE="$LOAD_BEFORE" META_LOAD_AFTER="$LOAD_AFTER"
export META_COMPILER="$("${CXX:-c++}" --version | head -1)"
export META_FLAGS="$(sed -n 's/^CMAKE_CXX_FLAGS_RELEASE:[A-Z]*=//p' "$BUILD_DIR/CMakeCache.txt")"
export META_COMMIT="$(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
if [[ -n "$(git --no-optional-locks status --porcelain 2>/dev/null | grep -v '^??' || true)" ]]; then
  export META_DIRTY=" with uncommitted changes in the working tree"
else
  export META_DIRTY=""
fi
export META_REPS="$REPS" META_RES="$RES"
export META_CMDS="$(printf '%s\n' \
  "build|${CONFIGURE[*]} && ${BUILD[*]}" \
  "Controller::step and scenario 3 (Google Benchmark)|${BENCH_CMD[*]}" \
  "cross-check of the prototype|${CLI_CMD[*]} > $RES/cli_s1_rac.json && $PY bench/prototype_rac.py --cli-json $RES/cli_s1_rac.json" \
  "CLI vs prototype, hyperfine|${HYPERFINE_CMD:-not run (hyperfine not installed)}" \
  "CLI vs prototype, interleaved loop|${LOOP_CMD[*]}" \
  "against the baseline build|${BASE_CMD:-not run (no BASELINE_BUILD)}" \
  "instruction counts|${CG_CMD:-not run}${BASE_CG_CMD:+; $BASE_CG_CMD}" \
  "all of the above|bench/run_bench.sh  (REPS=$REPS PY_RUNS=$PY_RUNS${BASE_SIM:+ BASELINE_BUILD=$BASELINE_BUILD BASE_RUNS=$BASE_RUNS})")"
"$PY" bench/perf_report.py meta --results "$RES"
mkdir -p "$(dirname "$OUT")"
"$PY" bench/perf_report.py report --results "$RES" --out "$OUT"
echo
echo "run_bench: wrote $OUT (raw results in $RES)"
