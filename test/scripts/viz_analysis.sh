#!/usr/bin/env bash
# analyze_bag and viz_markers: metrics against fixtures and hand-computed values, every error case.
exec /usr/bin/python3 -m unittest discover -s "$(dirname "$0")/../viz" -p 'test_*.py' -v
