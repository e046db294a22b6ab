#!/usr/bin/env bash
# scripts/slurm/submit_sweep + sweep_array.sbatch on a single-node Slurm that this
# test starts (slurmctld + slurmd on 127.0.0.1, a slurm.conf generated in a temp folder):
# 3 array tasks and the dependent merge job; the merged file must be byte-identical to the
# unsharded sweep. Then a sweep whose shard fails: the merge job must not run.
# The daemons run as root with AuthType=auth/none (no munge key to set up), so they run in a
# network namespace of their own (unshare -n: only its loopback), where nothing outside the
# test can reach them. Skipped, with the reason, when not root, when unshare or the Slurm
# daemons are missing, or when the cluster does not come up within 30 s.
#   Env: PMRAC_BUILD_DIR (default build).
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${PMRAC_BUILD_DIR:-$ROOT/build}
SWEEP=$BUILD/devel/lib/preadaptive_mrac/preadapt_sweep
skip() { echo "SKIPPED: slurm_sweep: $*"; exit 77; }

if [ "${PMRAC_SLURM_INSIDE:-}" != 1 ]; then
  [ -x "$SWEEP" ] || skip "$SWEEP not built"
  for c in slurmctld slurmd sbatch squeue sinfo unshare ip; do
    command -v "$c" >/dev/null || skip "$c not installed (apt-get install slurm-wlm iproute2)"
  done
  [ "$(id -u)" = 0 ] || skip "not root: slurmd must run as root to start jobs"
  unshare -n true 2>/dev/null || skip "cannot make a network namespace (unshare -n failed)"
  PMRAC_SLURM_INSIDE=1 exec unshare -n bash "$0" "$@"
fi

# --- inside the namespace
ip link set lo up || skip "cannot bring up lo in the namespace"
# Slurm binds with getaddrinfo(AI_ADDRCONFIG), which finds no IPv4 address where 127.0.0.1 is
# the only one; a second loopback address (still only this namespace's) makes it bind.
ip addr add 127.0.0.2/8 dev lo || skip "cannot add 127.0.0.2 to lo in the namespace"
W=$(mktemp -d "${TMPDIR:-/tmp}/slurm_sweep.XXXXXX")
PIDS=()
cleanup() {
  local p
  for p in "${PIDS[@]+"${PIDS[@]}"}"; do kill -TERM "$p" 2>/dev/null; done
  for _ in $(seq 1 50); do
    local alive=0
    for p in "${PIDS[@]+"${PIDS[@]}"}"; do kill -0 "$p" 2>/dev/null && alive=1; done
    [ "$alive" = 0 ] && break
    sleep 0.1
  done
  for p in "${PIDS[@]+"${PIDS[@]}"}"; do kill -KILL "$p" 2>/dev/null; done
  rm -rf "$W"
}
trap cleanup EXIT
free_port() { /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
H=$(hostname -s)
mkdir -p "$W/state" "$W/spool" "$W/log"
: >"$W/plugstack.conf"
cat >"$W/slurm.conf" <<CONF
ClusterName=pmractest
SlurmctldHost=$H(127.0.0.1)
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
AuthType=auth/none
CredType=cred/none
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$W/state
SlurmdSpoolDir=$W/spool
SlurmctldPidFile=$W/slurmctld.pid
SlurmdPidFile=$W/slurmd.pid
SlurmctldLogFile=$W/log/slurmctld.log
SlurmdLogFile=$W/log/slurmd.log
PlugStackConfig=$W/plugstack.conf
ProctrackType=proctrack/pgid
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
ReturnToService=2
MpiDefault=none
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
NodeName=$H NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=test Nodes=$H Default=YES MaxTime=10 State=UP
CONF
export SLURM_CONF=$W/slurm.conf
slurmctld -D -i -f "$SLURM_CONF" >"$W/log/slurmctld.out" 2>&1 &
PIDS+=($!)
slurmd -D -N "$H" -f "$SLURM_CONF" >"$W/log/slurmd.out" 2>&1 &
PIDS+=($!)
up=0
started=$(date +%s)
while [ $(($(date +%s) - started)) -lt 30 ]; do
  for p in "${PIDS[@]}"; do kill -0 "$p" 2>/dev/null || break 2; done
  timeout 5 sinfo -h -o '%t' 2>/dev/null | grep -qx idle && { up=1; break; }
  sleep 0.5
done
if [ "$up" = 0 ]; then
  echo "slurm_sweep: the single-node cluster did not come up; its logs:"
  tail -n 5 "$W"/log/* | sed 's/^/    /'
  skip "single-node Slurm did not come up (a daemon exited, or not idle within 30 s; logs above)"
fi
for p in "${PIDS[@]}"; do
  kill -0 "$p" 2>/dev/null || skip "a Slurm daemon exited at start: $(tail -n 3 "$W"/log/*.log)"
done
echo "slurm_sweep: single-node Slurm up ($(sinfo -h -o '%P %D %c %t'))"

# shellcheck source=test/scripts/lib/counts.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib/counts.sh"
wait_idle() {  # until no job is queued or running (at most $1 s)
  for _ in $(seq 1 $(($1 * 2))); do
    [ -z "$(timeout 5 squeue -h 2>&1)" ] && return 0
    sleep 0.5
  done
  return 1
}

export PMRAC_SWEEP_BIN=$SWEEP
ARGS=(--scenario 1 --modes rac,pa_learn --seeds 1-2
  --grid controller.attention.c_ed=0.015,0.02 --no-wall-time)
"$SWEEP" "${ARGS[@]}" --jobs 1 >"$W/all.jsonl" || bad "unsharded sweep exited $?"
if "$ROOT/scripts/slurm/submit_sweep" 3 "$W/out" -- "${ARGS[@]}" >"$W/submit.txt" 2>&1; then
  ok "submitted: $(cat "$W/submit.txt")"
else
  bad "submit_sweep failed: $(cat "$W/submit.txt")"
fi
wait_idle 120 || bad "jobs still queued after 120 s: $(squeue -h)"
n_shards=$(ls "$W/out"/shard_*.jsonl 2>/dev/null | wc -l)
[ "$n_shards" = 3 ] && ok "3 array tasks wrote their shards" ||
  bad "$n_shards shard files, expected 3 ($(cat "$W"/out/slurm_*.out 2>/dev/null))"
if [ -f "$W/out/sweep.jsonl" ] && cmp -s "$W/all.jsonl" "$W/out/sweep.jsonl"; then
  ok "merge job: sweep.jsonl == unsharded sweep (cmp, $(wc -l <"$W/out/sweep.jsonl") runs)"
else
  bad "merge job: sweep.jsonl missing or different ($(cat "$W"/out/slurm_merge_*.out 2>/dev/null))"
fi

# A shard that fails (a grid value the runs refuse at start: every task exits 2): the merge
# job depends on afterok, so it must never run and no sweep.jsonl may appear.
"$ROOT/scripts/slurm/submit_sweep" 2 "$W/bad" -- --scenario 1 --modes rac --seeds 1-2 \
  --grid controller.attention.c_ed=-1 --no-wall-time >"$W/submit2.txt" 2>&1 ||
  bad "submit_sweep (failing sweep) failed: $(cat "$W/submit2.txt")"
wait_idle 120 || bad "failing sweep: jobs still queued after 120 s: $(squeue -h)"
if [ ! -e "$W/bad/sweep.jsonl" ] && [ -z "$(ls "$W/bad"/slurm_merge_*.out 2>/dev/null)" ] &&
  grep -qs "c_ed" "$W"/bad/slurm_*_0.out; then
  ok "failing shard: the merge job did not run; the task's output names the key"
else
  bad "failing shard: a merge ran or the error is missing ($(cat "$W"/bad/*.out 2>/dev/null))"
fi

finish "slurm_sweep"
