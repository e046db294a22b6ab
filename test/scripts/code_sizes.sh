#!/usr/bin/env bash
# The size limits of src/ (docs/design.md "Layers"): no file over 600 lines, no C++ function
# over 150 lines, measured by scripts/code_sizes over every folder of src/ (a function from its
# signature's first line to its closing brace, comments and strings blanked, a lambda counted
# in the function that holds it). Prints each one over its limit.
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
# shellcheck source=test/scripts/lib/counts.sh
source "$ROOT/test/scripts/lib/counts.sh"
W=$(mktemp -d "${TMPDIR:-/tmp}/code_sizes.XXXXXX")
trap 'rm -rf "$W"' EXIT
PY=$(command -v python3 || echo /usr/bin/python3)
"$PY" "$ROOT/scripts/code_sizes" --functions src >"$W/out" 2>&1
rc=$?
if [ "$rc" = 0 ]; then
  ok "src/: $(grep -m1 '^longest files' "$W/out" | sed 's/.*(\(.*\)):/\1/'), none over 600 lines" \
    "nor a function over 150 ($(grep -m1 '^longest functions' "$W/out" | sed 's/.*(\(.*\)):/\1/'))"
else
  grep '^OVER: ' "$W/out" || cat "$W/out"
  bad "src/: over the limits (scripts/code_sizes --functions src exited $rc)"
fi
# The measure itself finds a function over a limit that some function exceeds.
if "$PY" "$ROOT/scripts/code_sizes" --functions src --max-function 20 >"$W/low" 2>&1; then
  bad "scripts/code_sizes --max-function 20 found nothing over (the measure counts nothing?)"
else
  ok "scripts/code_sizes --max-function 20 lists $(grep -c '^OVER: function' "$W/low") functions"
fi
finish code_sizes
