#!/usr/bin/env bash
# 100,000-row records through the CLI (issue 15): `bridgefit rcurve` (mbt,
# energy) and the load fit `bridgefit fit --fit-to load-displacement
# --calibrate-compliance=crack` on DCB-01 resampled with noise and faults,
# wall time and peak memory from /usr/bin/time -v.
#   bash bench/rcurve_rows_bench.sh [BUILD_DIR=build-bench] [OUT=out/bench/records]
set -euo pipefail
build=${1:-build-bench}
out=${2:-out/bench/records}
mkdir -p "$out"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DBRIDGEFIT_BUILD_BENCH=ON > /dev/null
cmake --build "$build" -j2 --target bf_rcurve_rows_bench bridgefit > /dev/null
"$build/bench/bf_rcurve_rows_bench" 100000 "$out/dcb01_100k.csv" | tee "$out/library.txt"
scene=data_samples/dcb_composite/scene.toml
measure() {  # name, command...
  local name=$1; shift
  /usr/bin/time -v "$@" > "$out/$name.out" 2> "$out/$name.time" || echo "$name: exit $?"
  printf '%-12s wall %s, peak %s kB\n' "$name" \
    "$(grep 'Elapsed (wall' "$out/$name.time" | awk '{print $NF}')" \
    "$(grep 'Maximum resident' "$out/$name.time" | awk '{print $NF}')" | tee -a "$out/cli.txt"
}
: > "$out/cli.txt"
measure rcurve_mbt "$build/apps/bridgefit" rcurve "$out/dcb01_100k.csv" --scene $scene --method mbt --json
measure rcurve_energy "$build/apps/bridgefit" rcurve "$out/dcb01_100k.csv" --scene $scene --method energy --json
measure fit_load "$build/apps/bridgefit" fit "$out/dcb01_100k.csv" --scene $scene \
  --fit-to load-displacement --calibrate-compliance=crack --law linear --resolution 0.6mm --json
