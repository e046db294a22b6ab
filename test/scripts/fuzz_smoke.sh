#!/usr/bin/env bash
# Smoke run of the libFuzzer targets (YAML config, weights file, incoming state messages):
# 10 s each. scripts/fuzz --seconds 600 is the real run.
set -euo pipefail
cd "$(dirname "$0")/../.."
if ! command -v clang++ >/dev/null; then
  echo "SKIPPED: clang++ is not installed (scripts/install_deps installs it)"
  exit 77
fi
scripts/fuzz --seconds "${FUZZ_SECONDS:-10}"
