#!/usr/bin/env bash
# Wall time of scenario 1 on JSBSim through preadapt_sim (60 s at dt 1 ms, 60,000 lockstep
# steps), RUNS times in a row, each under /work/bench.lock when that lock exists; prints each
# run's wall, user and system time, the load average before it, the median, and the CSV's
# sha256 (the same run must give the same bytes every time).
#
# Not a test: it passes or fails nothing.
#
#   bench/jsbsim_scenario1.sh [BUILD_DIR] [RUNS] [MODE] [SHARED_MEMORY]
#   defaults: build 3 pa_learn true (false: the bytes through loopback TCP, as JSBSim alone)
#
# Needs JSBSim (scripts/install_jsbsim, or PMRAC_JSBSIM).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
read -r BUILD_DIR RUNS MODE SHM <<<"${1:-build} ${2:-3} ${3:-pa_learn} ${4:-true}"
SIM="$BUILD_DIR/devel/bin/preadapt_sim"
[ -x "$SIM" ] || { echo "no $SIM: build preadapt_sim first" >&2; exit 1; }
export PMRAC_JSBSIM="${PMRAC_JSBSIM:-$(scripts/install_jsbsim | tail -n1)}"
LOCK=()
[ -e /work/bench.lock ] && LOCK=(flock /work/bench.lock)
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT

walls=()
for i in $(seq 1 "$RUNS"); do
  load="$(cut -d' ' -f1-3 /proc/loadavg)"
  "${LOCK[@]}" /usr/bin/time -f "%e %U %S" -o "$TMP/time" "$SIM" --scenario 1 --mode "$MODE" \
    --set plant.engine=jsbsim --set plant.jsbsim.shared_memory="$SHM" --json --csv "$TMP/run.csv" >"$TMP/run.json"
  read -r wall user sys <"$TMP/time"
  walls+=("$wall")
  printf 'run %d: %6.2f s wall, %5.2f s user, %5.2f s system (load before: %s) csv sha256 %s\n' \
    "$i" "$wall" "$user" "$sys" "$load" "$(sha256sum "$TMP/run.csv" | cut -c1-16)"
done
median="$(printf '%s\n' "${walls[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')"
echo "median of $RUNS: $median s wall (scenario 1, $MODE, plant.engine=jsbsim, shared_memory $SHM)"
