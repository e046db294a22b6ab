#!/usr/bin/env bash
# compare.launch rviz:=true included in a user's <group ns="cmp">, under Xvfb: rviz
# (remapped by the launch file) subscribes to /cmp/tf and /cmp/aircraft_markers, the pa pair's
# viz_markers publishes the latter from /cmp/pa (scripts/lib/parent_names), the screenshot shows
# the aircraft, arrow, text and alpha history, no display in error. Exit 77 (skipped, said)
# where Xvfb or rviz is absent.
exec bash "$(dirname "$0")/../viz/rviz_screenshot_test.sh" --launch "preadaptive_mrac compare.launch" \
  --ns cmp "$@"
