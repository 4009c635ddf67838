#!/usr/bin/env bash
# Regenerates the synthetic samples data_samples/mdf_ct and data_samples/pb_ct
# with bridgefit's own reduced forward model (bridgefit synth). Reproducible:
# the same seed gives the same files. Usage: scripts/make_samples.sh [path/to/bridgefit]
#   record.csv        noisy record (0.5% load, 1 um displacement, 0.3 mm crack length)
#   record_exact.csv  the same test without noise (rounded to the printed digits)
#   images/           10 speckle frames (400x300, 8 bit) and truth.csv
set -euo pipefail
cd "$(dirname "$0")/.."
BF=${1:-build/apps/bridgefit}
for sample in mdf_ct:1 pb_ct:2; do
  name=${sample%%:*}; seed=${sample##*:}
  "$BF" synth "data_samples/$name/scene.toml" --out "data_samples/$name" --seed "$seed" --quiet
  "$BF" synth "data_samples/$name/scene.toml" --out "data_samples/$name" --seed "$seed" --quiet \
    --load-noise 0 --displacement-noise 0um --crack-noise 0mm --frames 0 --record-name record_exact.csv
done
