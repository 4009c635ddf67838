#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, runs the whole suite.
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ "${1:-}" == "--sanitize" ]]; then
  shift
  bash scripts/setup.sh
  exec bash scripts/test_sanitize.sh "$@"
fi
start=$(date +%s)
bash scripts/setup.sh
bash scripts/build.sh
jobs=$(nproc 2>/dev/null || echo 2)
ctest --test-dir build --output-on-failure -j"$jobs" --timeout 600
echo "test.sh: finished in $(( $(date +%s) - start )) s"
