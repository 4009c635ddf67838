#!/usr/bin/env bash
# Regenerates docs/rcurve_dcb_methods.png: R curves of the real DCB tests by
# method (docs/RCURVE_METHODS.md). Usage: docs/rcurve_dcb_methods.sh [path/to/bridgefit]
set -euo pipefail
cd "$(dirname "$0")/.."
BF=${1:-build/apps/bridgefit}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
MAP="--columns time=Time,displacement=Disp,load=Force,crack_length=CrackExt --units time=s,displacement=mm,load=N,crack_length=mm"
for f in DCB-01 DCB-02; do
  for m in mbt cc equivalent; do
    "$BF" rcurve tests/data/experiment/${f}_Toughness.csv --scene data_samples/dcb_composite/scene.toml \
      --method $m $MAP --csv "$TMP/${f}_$m.csv" --quiet > /dev/null
  done
  "$BF" rcurve tests/data/experiment/${f}_Toughness.csv --scene data_samples/dcb_composite/scene.toml \
    --method energy $MAP --csv "$TMP/${f}_energy.csv" --quiet > /dev/null
done
gnuplot <<GP
set terminal pngcairo size 1400,560 font "DejaVu Sans,11"
set output "docs/rcurve_dcb_methods.png"
set datafile separator ","
set datafile missing "NaN"
set multiplot layout 1,2 title "Real DCB tests (tests/data/experiment): R curves by method"
set xlabel "crack length a [mm] (equivalent: a_e - |Delta|)"
set ylabel "R [J/m^2]"
set key bottom right
set grid
set yrange [0:1800]
do for [f in "DCB-01 DCB-02"] {
  set title f
  plot "$TMP/".f."_energy.csv" every ::1 u 1:2:3 w yerrorbars pt 7 ps 1.0 lw 1.5 lc rgb "#d62728" t "energy (default increments, +- k=2)", \
       "tests/data/experiment/".f."_Toughness.csv" every ::1 u 4:(\$5 > 0 ? 1000*\$5 : 1/0) w l lw 4 lc rgb "#bbbbbb" t "authors' G_I", \
       "$TMP/".f."_mbt.csv" every ::1 u 1:2 w l lw 1.5 lc rgb "#1f77b4" t "MBT", \
       "$TMP/".f."_cc.csv" every ::1 u 1:2 w l lw 1.5 lc rgb "#2ca02c" t "CC", \
       "$TMP/".f."_equivalent.csv" every ::1 u 1:2 w l lw 1.5 dt 2 lc rgb "#9467bd" t "equivalent crack"
}
unset multiplot
GP
echo "wrote docs/rcurve_dcb_methods.png"
