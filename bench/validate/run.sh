#!/usr/bin/env bash
# Issue 17's validation campaign, one command (docs/VALIDATION.md):
#   bash bench/validate/run.sh [cases=300] [seed=17] [jobs=2]
# Configures and builds bf_validate in $BUILD_DIR (default build-validate,
# Release, -DBRIDGEFIT_BUILD_BENCH=ON; ccache when found), then runs it into
# $OUT_DIR (default out/validate): validation.csv (one row per case),
# validation_summary.txt (table, every failure), validation.png (gnuplot).
# VALIDATE_MAX_WALL_S > 0: no case starts after that many seconds.
set -euo pipefail
cd "$(dirname "$0")/../.."
cases=${1:-300}
seed=${2:-17}
jobs=${3:-2}
build=${BUILD_DIR:-build-validate}
out=${OUT_DIR:-out/validate}
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DBRIDGEFIT_BUILD_BENCH=ON "${launcher[@]}" >/dev/null
cmake --build "$build" -j"$jobs" --target bf_validate
# Cases run side by side, each serial inside: one thread per job.
export OMP_NUM_THREADS=1
start=$(date +%s)
status=0
"$build/bench/bf_validate" "$cases" "$seed" "$jobs" "$out" 0 "${VALIDATE_MAX_WALL_S:-0}" || status=$?
echo "wall: $(( $(date +%s) - start )) s on $(nproc --all) cores; outputs in $out"
exit "$status"
