#!/usr/bin/env bash
# scripts/live_plot under Xvfb against a realtime scenario.launch (a 10 s scenario):
# three rqt_plot-style arguments (/controller/status/e, /plant/state/x[1],
# /controller/status/theta_hat_0:theta_hat_1), a 5 s scrolling window. Checks: live_plot
# printed a non-zero point count for each of the 4 lines; the saved figure and a screenshot
# of the X display both hold pixels of matplotlib's first four line colours; a field the
# message lacks is refused with exit 2 naming it.
#   Env: PMRAC_BUILD_DIR (default build).
set -uo pipefail
PY=/usr/bin/python3
TEST_NAME=live_plot
# shellcheck source=test/scripts/lib/ros_build.sh
source "$(dirname "$0")/lib/ros_build.sh"
command -v Xvfb >/dev/null || skip "Xvfb not installed (apt-get install xvfb)"
"$PY" -c 'import matplotlib, tkinter, rospy, genpy, PIL' 2>/dev/null ||
  skip "$PY lacks matplotlib, tkinter, rospy, genpy or PIL"
export PMRAC_BUILD_DIR=$BUILD
W=$(mktemp -d "${TMPDIR:-/tmp}/live_plot_test.XXXXXX")
PIDS=()
cleanup() {
  local p
  for p in "${PIDS[@]+"${PIDS[@]}"}"; do kill -INT -- "-$p" 2>/dev/null; done
  sleep 1
  for p in "${PIDS[@]+"${PIDS[@]}"}"; do kill -KILL -- "-$p" 2>/dev/null; done
}
trap cleanup EXIT
# shellcheck source=test/scripts/lib/counts.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib/counts.sh"

setsid Xvfb -displayfd 3 -screen 0 1024x768x24 -nolisten tcp -noreset 3>"$W/display" \
  >"$W/xvfb.log" 2>&1 &
PIDS+=($!)
for _ in $(seq 1 100); do [ -s "$W/display" ] && break; sleep 0.1; done
[ -s "$W/display" ] || { bad "Xvfb did not start"; exit 1; }
export DISPLAY=:$(head -n1 "$W/display")

cat >"$W/short.yaml" <<YAML
scenario:
  name: live_plot_short
  description: "10 s: theta 0.1, then 2 from 3 s"
  theta:
    - {until: 3.0, scale: 0.1}
    - {until: 10.0, scale: 2.0}
YAML
PORT=$("$PY" -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
export ROS_MASTER_URI=http://127.0.0.1:$PORT ROS_HOME=$W/home ROS_LOG_DIR=$W/log
# shellcheck source=scripts/lib/ros_env
source "$ROOT/scripts/lib/ros_env"
setsid "$ROOT/scripts/lib/launch_checked" --quiet --timeout 60 --log "$W/launch.log" -- \
  -p "$PORT" preadaptive_mrac scenario.launch scenario:="$W/short.yaml" clock:=realtime \
  output:=log >"$W/lc.out" 2>&1 &
PIDS+=($!)
LAUNCH=$!
SPECS=(/controller/status/e /plant/state/x[1] /controller/status/theta_hat_0:theta_hat_1)
"$PY" "$ROOT/scripts/live_plot" "${SPECS[@]}" --window 5 --duration 14 --wait 20 \
  --title "live_plot test" --save "$W/saved.png" >"$W/plot.out" 2>&1 &
PLOT=$!
# A field the message does not have (while the master runs): exit 2, named.
"$PY" "$ROOT/scripts/live_plot" /plant/state/no_such_field --headless --save "$W/x.png" \
  --duration 20 --wait 20 >"$W/bad.out" 2>&1 &
BAD=$!
sleep 11
"$PY" -c 'import sys; from PIL import ImageGrab; ImageGrab.grab(xdisplay=sys.argv[2]).save(sys.argv[1])' \
  "$W/screen.png" "$DISPLAY" 2>"$W/shot.err" || bad "screenshot failed: $(cat "$W/shot.err")"
wait "$PLOT"
rc=$?
wait "$BAD"
brc=$?
wait "$LAUNCH" || bad "the launch failed: $(cat "$W/lc.out")"
cat "$W/plot.out"
[ "$rc" = 0 ] && ok "live_plot exited 0" || bad "live_plot exited $rc"
for label in /controller/status/e /plant/state/x[1] /controller/status/theta_hat_0 \
  /controller/status/theta_hat_1; do
  n=$(grep -F "live_plot: $label: " "$W/plot.out" | sed 's/.*: \([0-9]*\) points/\1/')
  if [ -n "$n" ] && [ "$n" -gt 100 ]; then ok "$label: $n points"; else bad "$label: ${n:-no} points"; fi
done
# matplotlib's first colours (C0..C3) in the figure: each line drawn.
check_colours() {
  "$PY" - "$1" <<'PYEOF'
import sys
from PIL import Image
img = Image.open(sys.argv[1]).convert('RGB')
px = img.getdata()
want = {'C0 blue': (31, 119, 180), 'C1 orange': (255, 127, 14), 'C2 green': (44, 160, 44),
        'C3 red': (214, 39, 40)}
bad = 0
for name, c in want.items():
    n = sum(1 for p in px if all(abs(p[i] - c[i]) <= 12 for i in range(3)))
    print('%s: %d pixels' % (name, n))
    bad += n < 30
sys.exit(1 if bad else 0)
PYEOF
}
for img in saved screen; do
  if [ -s "$W/$img.png" ] && out=$(check_colours "$W/$img.png"); then
    ok "$img.png: the 4 line colours are drawn ($(tr '\n' ' ' <<<"$out"))"
  else
    bad "$img.png: a line colour is missing ($(tr '\n' ' ' <<<"${out:-no image}"))"
  fi
done
if [ "$brc" = 2 ] && grep -q "no field no_such_field" "$W/bad.out"; then
  ok "unknown field refused: $(grep error "$W/bad.out")"
else
  bad "unknown field: exit $brc: $(cat "$W/bad.out")"
fi
mkdir -p "$W/keep" && cp "$W"/*.png "$W/keep/" 2>/dev/null
echo "images: $W/keep"
finish "live_plot"
