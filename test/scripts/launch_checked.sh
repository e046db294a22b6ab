#!/usr/bin/env bash
# scripts/lib/launch_checked against a stand-in roslaunch that prints recorded roslaunch output
# (formats of Debian 12's roslaunch 1.15): a normal end, a required node refusing its
# parameters, a node that is not required dying, roslaunch failing while it starts nodes, a
# node's FATAL lines only in its own log file (output="log"), a node killed by a signal,
# missing or incomplete plant reports, and --timeout. No ROS needed.
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
CHECKED=$ROOT/scripts/lib/launch_checked
W=$(mktemp -d "${TMPDIR:-/tmp}/launch_checked_test.XXXXXX")
trap 'rm -rf "$W"' EXIT
mkdir -p "$W/bin" "$W/logs"
cat >"$W/bin/roslaunch" <<'FAKE'
#!/usr/bin/env bash
[ -n "${FAKE_SLEEP:-}" ] && exec sleep "$FAKE_SLEEP"
cat "$FAKE_LOG"
exit "${FAKE_RC:-0}"
FAKE
chmod +x "$W/bin/roslaunch"
export PATH="$W/bin:$PATH"
E=$'\e'
# shellcheck source=test/scripts/lib/counts.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib/counts.sh"

# expect NAME WANT_RC PATTERN_ON_STDERR|"" [launch_checked options...]
expect() {
  local name=$1 want=$2 pattern=$3 rc
  shift 3
  "$CHECKED" --log "$W/out.log" --quiet "$@" -- fake.launch >"$W/stdout" 2>"$W/stderr"
  rc=$?
  if [ "$rc" != "$want" ]; then
    bad "$name: exit code $rc, expected $want"; sed 's/^/    /' "$W/stderr"; return
  fi
  if [ -n "$pattern" ] && ! grep -qE -- "$pattern" "$W/stderr"; then
    bad "$name: stderr lacks /$pattern/"; sed 's/^/    /' "$W/stderr"; return
  fi
  if [ "$want" = 0 ] && [ -s "$W/stderr" ]; then
    bad "$name: stderr not empty on success"; sed 's/^/    /' "$W/stderr"; return
  fi
  ok "$name"
}

L=$W/logs/run
# 1. normal end: the required plant finishes cleanly, the others are killed on exit.
cat >"$W/normal.log" <<EOF
process[plant_sim-2]: started with pid [100]
process[mrac_controller-3]: started with pid [101]
${E}[0m[ INFO] [1795395444.797318750]: plant_sim: scenario complete after 6000 of 6000 steps${E}[0m
${E}[31m================================================================================REQUIRED process [plant_sim-2] has died!
process has finished cleanly
log file: $L/plant_sim-2*.log
Initiating shutdown!
================================================================================${E}[0m
[mrac_controller-3] killing on exit
EOF
FAKE_LOG=$W/normal.log expect "normal end" 0 ""

# 2. the required controller refuses a key (output="screen").
cat >"$W/required.log" <<EOF
process[plant_sim-2]: started with pid [100]
process[mrac_controller-3]: started with pid [101]
${E}[31m[FATAL] [1795395366.579974377]: /mrac_controller: refusing to start, 1 parameter problem(s):${E}[0m
${E}[31m[FATAL] [1795395366.580006014]:   /mrac_controller/controller/lqr/R: expected a number, got string 'oops'${E}[0m
${E}[31m================================================================================REQUIRED process [mrac_controller-3] has died!
process has died [pid 101, exit code 2, cmd /x/mrac_controller_node __name:=mrac_controller __log:=$L/mrac_controller-3.log].
log file: $L/mrac_controller-3*.log
Initiating shutdown!
================================================================================${E}[0m
[plant_sim-2] killing on exit
EOF
FAKE_LOG=$W/required.log expect "required node refuses a key: exit 2, key named" 2 \
  '^launch_checked:   \[FATAL\]   /mrac_controller/controller/lqr/R: expected a number'
FAKE_LOG=$W/required.log expect "the dead node is named" 2 'node \[mrac_controller-3\] died with exit code 2'

# 2b. nodelet shape: the controller nodelet refuses a key, the required manager ends with 2,
# and a loader that was still loading the plant dies first (255): the refusal's code wins.
cat >"$W/nodelet.log" <<EOF
process[pmrac_manager-2]: started with pid [100]
process[plant_sim-3]: started with pid [101]
process[mrac_controller-4]: started with pid [102]
${E}[31m[FATAL] [1795395366.579974377]: /mrac_controller: refusing to start, 1 parameter problem(s):${E}[0m
${E}[31m[FATAL] [1795395366.580006014]:   /mrac_controller/controller/robust/cl_gain: expected a finite number, got nan${E}[0m
${E}[31m[FATAL] [1795395366.680006014]: Failed to load nodelet of type preadaptive_mrac/PlantSim${E}[0m
${E}[31m[plant_sim-3] process has died [pid 101, exit code 255, cmd /usr/lib/nodelet/nodelet load preadaptive_mrac/PlantSim /pmrac_manager __name:=plant_sim].${E}[0m
${E}[31m================================================================================REQUIRED process [pmrac_manager-2] has died!
process has died [pid 100, exit code 2, cmd /x/pmrac_manager __name:=pmrac_manager __log:=$L/pmrac_manager-2.log].
log file: $L/pmrac_manager-2*.log
Initiating shutdown!
================================================================================${E}[0m
[mrac_controller-4] killing on exit
EOF
FAKE_LOG=$W/nodelet.log expect "nodelet refuses a key, a loader dies first: exit 2" 2 \
  '^launch_checked:   \[FATAL\]   /mrac_controller/controller/robust/cl_gain: expected a finite'

# 3. a node that is not required dies (3), then the required plant ends cleanly.
cat >"$W/notrequired.log" <<EOF
${E}[31m[mrac_controller-3] process has died [pid 101, exit code 3, cmd /x/mrac_controller_node].${E}[0m
${E}[31m[ERROR] [1795395387.025046420, 0.000000001]: no plant after 15.0 s (~start_timeout)${E}[0m
REQUIRED process [plant_sim-2] has died!
process has finished cleanly
EOF
FAKE_LOG=$W/notrequired.log expect "node not required dies: exit 3" 3 '\[ERROR\] no plant after 15.0 s'

# 4. roslaunch itself fails (exit 1) while starting nodes after a required one died.
cat >"$W/rlexception.log" <<EOF
[FATAL] [1795395447.516811657]:   /rac/mrac_controller/controller/lqr/R: expected a number, got string 'oops'
================================================================================REQUIRED process [rac/mrac_controller-3] has died!
process has died [pid 14537, exit code 2, cmd /x/mrac_controller_node __name:=mrac_controller].
log file: $L/rac-mrac_controller-3*.log
Initiating shutdown!
================================================================================
RLException: cannot add process [run_monitor-6] after process monitor has been shut down
EOF
FAKE_LOG=$W/rlexception.log FAKE_RC=1 expect "roslaunch fails after a required node died: exit 2" 2 \
  'roslaunch exited with code 1'

# 4b. ... and leaves the master and nodes it started running: they are stopped (found by the
# run id in their __log:= argument, since this roslaunch started its own master).
RUN=0000abcd-e6d8-11f1-a993-02fc00000001
python3 -c 'import time; time.sleep(120)' "__log:=$W/logs/$RUN/master.log" &
LEFTOVER=$!
disown "$LEFTOVER"
{ echo "auto-starting new master"; echo "setting /run_id to $RUN"; cat "$W/rlexception.log"; } \
  >"$W/leftover.log"
FAKE_LOG=$W/leftover.log FAKE_RC=1 expect "roslaunch leaves its master behind: stopped" 2 \
  "left 1 process\(es\) of its run behind \(pids $LEFTOVER\): stopped"
if kill -0 "$LEFTOVER" 2>/dev/null; then
  bad "the leftover process $LEFTOVER is still running"; kill "$LEFTOVER"
else
  ok "the leftover process is gone"
fi
# A roslaunch that used a master it did not start leaves that master's processes alone.
python3 -c 'import time; time.sleep(120)' "__log:=$W/logs/$RUN/master.log" &
OTHER=$!
disown "$OTHER"
{ echo "setting /run_id to $RUN"; cat "$W/rlexception.log"; } >"$W/external.log"
FAKE_LOG=$W/external.log FAKE_RC=1 expect "an external master's processes are left alone" 2 ""
if kill -0 "$OTHER" 2>/dev/null; then
  ok "the external master's process still runs"; kill "$OTHER"
else
  bad "a process of an external master was stopped"
fi

# 5. output="log": the FATAL lines are only in the node's own log file.
mkdir -p "$L"
printf '[FATAL] [1795395366.5]:   /plant_sim/scenario/theta/0/until: missing (required)\n' \
  >"$L/plant_sim-2-stdout.log"
cat >"$W/outputlog.log" <<EOF
================================================================================REQUIRED process [plant_sim-2] has died!
process has died [pid 100, exit code 2, cmd /x/plant_sim_node __name:=plant_sim].
log file: $L/plant_sim-2*.log
Initiating shutdown!
EOF
FAKE_LOG=$W/outputlog.log expect "key read from the dead node's log file" 2 \
  '/plant_sim/scenario/theta/0/until: missing'

# 6. killed by a signal.
printf '[viz-4] process has died [pid 9, exit code -11, cmd /x/viz].\nREQUIRED process [plant_sim-2] has died!\nprocess has finished cleanly\n' \
  >"$W/signal.log"
FAKE_LOG=$W/signal.log expect "node killed by a signal: exit 1" 1 'killed by signal 11'

# 7. plant reports.
printf '{"steps": 6000, "total_steps": 6000, "completed": true, "wall_time_s": 1.0}\n' >"$W/ok.json"
printf '{"steps": 10, "total_steps": 6000, "completed": false, "wall_time_s": 1.0}\n' >"$W/stopped.json"
FAKE_LOG=$W/normal.log expect "report complete" 0 "" --expect-report "$W/ok.json"
FAKE_LOG=$W/normal.log expect "report missing: exit 1" 1 "result file is missing" \
  --expect-report "$W/none.json"
FAKE_LOG=$W/normal.log expect "report incomplete: exit 1" 1 "did not complete" \
  --expect-report "$W/stopped.json"
FAKE_LOG=$W/normal.log expect "expected file missing: exit 1" 1 "expected file missing" \
  --expect "$W/none.bag"

# 8. --timeout.
FAKE_SLEEP=30 FAKE_LOG=/dev/null expect "--timeout: exit 124" 124 "did not end within 1 s" --timeout 1

finish "launch_checked test"
