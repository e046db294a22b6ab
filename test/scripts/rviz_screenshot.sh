#!/usr/bin/env bash
# rviz under Xvfb with rviz/preadaptive_mrac.rviz against a running scenario: screenshot not
# blank, markers drawn, no display in error. Exit 77 (skipped, said) where Xvfb is absent.
exec bash "$(dirname "$0")/../viz/rviz_screenshot_test.sh"
