#!/usr/bin/env bash
# Every speed-versus-accuracy bench in one run (issue 8): builds the bench
# targets (Release, -DBRIDGEFIT_BUILD_BENCH=ON), runs them, and writes into one
# folder each bench's table, a gnuplot chart of time against error, and
# summary.md (the machine, the command, every point of the charts in one table,
# then each bench's own table).
#
#   bash bench/run_all.sh [--quick] [--out DIR] [--build DIR] [--jobs N]
#                         [--only reduced,mpm,dic,fit] [--no-build]
#
#   --quick     smoke run with coarse settings (about 30 s once built);
#               checks the chain, its figures are not for the README
#   --out       output folder (default out/bench)
#   --build     CMake build folder (default build)
#   --only      run only these benches (default all)
#   --no-build  use the bench executables already in the build folder
#
# Benches (bench/*.cmake):
#   reduced  bf_models_bench    reduced model at element sizes h: time per R curve
#                               against the error of R - J_tip,c (Richardson reference)
#   mpm      bf_mpm_bench       MPM on the CT at cell sizes, 1 and 2 threads: wall
#                               time against the J error (E399) and compliance error
#                               (Saxena-Hudak); stationary crack
#            bf_mpm_growth_bench  MPM with crack growth (issue 5), half and full
#                               model: wall time per R curve against the R and
#                               R_energy errors (reference: reduced model at
#                               0.25 mm); see run_mpm_growth
#   dic      dic_speed          IC-GN at subset sizes, first/second-order shape
#                               functions, 1 and 2 threads: time per point against
#                               RMS(u - exact) on DIC Challenge Sample 14 L1;
#            dic_sample15       (table only) subset size against smearing of a step
#   fit      bf_inverse_bench   every optimizer on the three issue-7 cases: CPU time
#                               per fit against the largest parameter error
#            bf_fit_load_bench  the load-displacement fit: CPU time per fit against
#                               sigma_c's error over noise draws, per element size
#
# Timings are wall clock unless a column says CPU; the load average before and
# after each bench is in summary.md (on a shared machine wall times are upper
# bounds, CPU seconds are the robust figure).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT"

QUICK=0
OUT=out/bench
BUILD=build
JOBS=2
ONLY=reduced,mpm,dic,fit
BUILD_BENCHES=1
COMMAND_LINE="bash bench/run_all.sh $*"
while [[ $# -gt 0 ]]; do
  case $1 in
    --quick) QUICK=1 ;;
    --out) OUT=$2; shift ;;
    --build) BUILD=$2; shift ;;
    --jobs) JOBS=$2; shift ;;
    --only) ONLY=$2; shift ;;
    --no-build) BUILD_BENCHES=0 ;;
    -h|--help) awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; exit 0 ;;
    *) echo "run_all.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
wants() { [[ ",$ONLY," == *",$1,"* ]]; }
command -v gnuplot > /dev/null || { echo "run_all.sh: gnuplot is needed for the charts" >&2; exit 1; }

# Settings: full run (README figures) and --quick (smoke).
if [[ $QUICK == 1 ]]; then
  REDUCED_H=4,2,1,0.5          # mm; each half the previous, >= 3
  MPM_CELLS=5; MPM_THREADS=1   # mm
  DIC_STEP=4; DIC_SUBSETS=21,33; DIC_THREADS=1
  FIT_H=2                      # mm, reduced-model elements inside the fits
  LOAD_FIT_DRAWS=2; LOAD_FIT_H=2,1  # load-displacement fit: noise draws, element sizes (mm)
else
  REDUCED_H=4,2,1,0.5,0.25,0.125
  MPM_CELLS=5,2.5,1.25; MPM_THREADS=1,2
  DIC_STEP=2; DIC_SUBSETS=15,21,27,33,41; DIC_THREADS=1,2
  FIT_H=0.5
  LOAD_FIT_DRAWS=10; LOAD_FIT_H=2,1,0.5
fi

mkdir -p "$OUT/logs"
OUT=$(cd "$OUT" && pwd)
BENCH_DIR=$BUILD/bench
T_START=$(date +%s)
STEPS=""   # markdown rows: bench | wall s | load before | load after

load() { cut -d' ' -f1-3 /proc/loadavg; }
# step NAME CMD...: runs CMD with stdout+stderr in logs/NAME.log, records time and load.
step() {
  local name=$1; shift
  local before t0 rc=0
  before=$(load); t0=$(date +%s.%N)
  echo "--- $name: $*" >&2
  "$@" > "$OUT/logs/$name.log" 2>&1 || rc=$?
  local wall
  wall=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  STEPS+="| $name | $wall | $before | $(load) | $rc |"$'\n'
  if [[ $rc != 0 ]]; then
    echo "run_all.sh: $name failed (exit $rc), see $OUT/logs/$name.log" >&2
    tail -5 "$OUT/logs/$name.log" >&2
    return $rc
  fi
}

# pick CSV "col1;col2;..." -> whitespace table of those columns, chosen by
# header name (trimmed; lines starting with # skipped). Stable if a bench adds
# or reorders columns.
pick() {
  awk -F',' -v want="$2" '
    BEGIN { n = split(want, w, ";") }
    /^#/ { next }
    !header {
      for (i = 1; i <= NF; i++) { g = $i; gsub(/^ +| +$/, "", g); idx[g] = i }
      for (k = 1; k <= n; k++)
        if (!(w[k] in idx)) { print "pick: no column \"" w[k] "\" in " FILENAME > "/dev/stderr"; exit 3 }
      header = 1; next
    }
    { line = ""
      for (k = 1; k <= n; k++) { v = $(idx[w[k]]); gsub(/^ +| +$/, "", v); line = line (k > 1 ? " " : "") v }
      print line }' "$1"
}
# md_table CSV "col1;col2;..." -> markdown table of those columns ('|' in a
# name is escaped).
md_table() {
  local names=${2//|/\\|}
  echo "| ${names//;/ | } |"
  echo "|$(echo "$2" | awk -F';' '{ for (i = 1; i <= NF; i++) printf "---|" }')"
  pick "$1" "$2" | awk '{ printf "|"; for (i = 1; i <= NF; i++) printf " %s |", $i; print "" }'
}
# to_csv FILE FIRST: the whitespace table whose header starts with FIRST -> CSV
# (other lines, e.g. warnings, and rows of another width are left out).
to_csv() {
  awk -v first="$2" '!n && $1 == first { n = NF } n && NF == n { $1 = $1; gsub(/ /, ","); print }' "$1"
}
plot() { (cd "$OUT" && gnuplot "$1" > "logs/${1%.gp}.gnuplot.log" 2>&1) || echo "gnuplot $1 failed" >&2; }
GP_HEAD="set terminal pngcairo size 900,600 font ',11'
set logscale xy
set grid
set key top right"

# ---------------------------------------------------------------- build
if [[ $BUILD_BENCHES == 1 ]]; then
  step configure cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DBRIDGEFIT_BUILD_BENCH=ON
  TARGETS=()
  wants reduced && TARGETS+=(bf_models_bench)
  wants mpm && TARGETS+=(bf_mpm_bench)
  wants dic && TARGETS+=(dic_speed dic_sample15)
  wants fit && TARGETS+=(bf_inverse_bench bf_fit_load_bench)
  # MPM crack growth (issue 5): built when bench/*.cmake defines it.
  # (the target list is read whole: grep -q would end the pipe early and, with
  # pipefail, read as "absent")
  if wants mpm && [[ $(cmake --build "$BUILD" --target help 2> /dev/null) == *bf_mpm_growth_bench* ]]; then
    TARGETS+=(bf_mpm_growth_bench)
  fi
  step build cmake --build "$BUILD" -j "$JOBS" --target "${TARGETS[@]}"
fi

# ---------------------------------------------------------------- reduced model
ROWS=""  # the combined table: bench | setting | time | error
if wants reduced; then
  step reduced env OMP_NUM_THREADS=1 "$BENCH_DIR/bf_models_bench" "$OUT/reduced_bench" "$REDUCED_H"
  pick "$OUT/reduced_bench.csv" "resolution [mm];R curve median [ms];max error R-J_tip_c [%];max error R [%]" \
    > "$OUT/reduced_bench.dat"
  cat > "$OUT/reduced_bench.gp" << EOF
$GP_HEAD
set output 'reduced_bench.png'
set title 'Reduced model (CT, linear law): time per R curve against error, one core'
set xlabel 'time per R curve [ms] (median)'
set ylabel 'largest error at a = 46, 54, 62, 70 mm [%]'
plot 'reduced_bench.dat' using 2:3 with linespoints pt 7 lw 2 title 'R - J_{tip,c}', \\
     '' using 2:4 with linespoints pt 5 lw 2 title 'R', \\
     '' using 2:3:(sprintf('h = %s mm', stringcolumn(1))) with labels offset 1,1 left notitle
EOF
  plot reduced_bench.gp
  ROWS+=$(awk '{ printf "| reduced model | h = %s mm | %s ms per R curve | %s %% (R - J_tip,c) |\n", $1, $2, $3 }' \
    "$OUT/reduced_bench.dat")$'\n'
fi

# ---------------------------------------------------------------- MPM
# MPM crack growth (issue 5): bf_mpm_growth_bench, when the build has it,
# writes mpm_growth_bench.csv (per sigma_c, half/full model and cell: wall time
# per R curve and the largest R and R_energy errors against the reduced model
# at 0.25 mm), mpm_growth_bench_curves.csv and its own chart
# mpm_growth_bench.png. A later MPM R-curve bench plugs in here the same way:
# run it, then add its table to mpm_growth.md and its points to ROWS.
run_mpm_growth() {
  local exe=$BENCH_DIR/bf_mpm_growth_bench
  if [[ ! -x $exe ]]; then
    echo "No MPM crack-growth bench in this build (bf_mpm_growth_bench, issue 5): skipped." \
      > "$OUT/mpm_growth.md"
    return 0
  fi
  local quick_flag=()
  [[ $QUICK == 1 ]] && quick_flag=(--quick)
  step mpm-growth "$exe" "$OUT/mpm_growth_bench" "${quick_flag[@]}"
  {
    echo "![MPM crack growth](mpm_growth_bench.png)"; echo
    md_table "$OUT/mpm_growth_bench.csv" "sigma_c [MPa];model;cell [mm];particles;wall [s];max |R error| [%];max |R_energy error| [%];steady state onset [mm];reference onset [mm]"
  } > "$OUT/mpm_growth.md"
  ROWS+=$(pick "$OUT/mpm_growth_bench.csv" "sigma_c [MPa];model;cell [mm];wall [s];max |R_energy error| [%];max |R error| [%]" |
    awk '{ printf "| MPM crack growth | sigma_c %s MPa, %s model, %s mm cells | %s s per R curve | %s %% (R_energy), %s %% (R) |\n", $1, $2, $3, $4, $5, $6 }')$'\n'
}

if wants mpm; then
  step mpm env OMP_WAIT_POLICY=passive "$BENCH_DIR/bf_mpm_bench" --cells "$MPM_CELLS" \
    --threads "$MPM_THREADS" --csv "$OUT/mpm_bench.csv"
  pick "$OUT/mpm_bench.csv" "cell_mm;threads;wall_s;cpu_s;J_err_pct;C_err_pct;Mparticle_steps_per_s" |
    sort -k2,2n -k1,1gr > "$OUT/mpm_bench.dat"  # one series after the other
  cat > "$OUT/mpm_bench.gp" << EOF
$GP_HEAD
set output 'mpm_bench.png'
set title 'MPM, CT a/W = 0.3, stationary crack: wall time against error'
set xlabel 'wall time per run [s]'
set ylabel '|error| [%]'
plot for [t=1:2] 'mpm_bench.dat' using 3:(\$2 == t ? abs(\$5) : 1/0) with linespoints pt 7 lw 2 \\
       title sprintf('J vs E399, %d thread(s)', t), \\
     for [t=1:2] '' using 3:(\$2 == t ? abs(\$6) : 1/0) with linespoints pt 5 lw 2 dt 2 \\
       title sprintf('compliance vs Saxena-Hudak, %d thread(s)', t), \\
     '' using 3:(\$2 == 1 ? abs(\$5) : 1/0):(sprintf('%s mm', stringcolumn(1))) \\
       with labels offset 1,1 left notitle
EOF
  plot mpm_bench.gp
  ROWS+=$(awk '{ printf "| MPM (stationary) | %s mm cells, %s thread(s) | %s s wall (%s CPU s) | %s %% (J), %s %% (compliance) |\n", $1, $2, $3, $4, $5, $6 }' \
    "$OUT/mpm_bench.dat")$'\n'
  run_mpm_growth
fi

# ---------------------------------------------------------------- DIC
if wants dic; then
  step dic env OMP_WAIT_POLICY=passive "$BENCH_DIR/dic_speed" "$ROOT/tests/data/dic" "$DIC_STEP" \
    "$DIC_SUBSETS" "$DIC_THREADS"
  to_csv "$OUT/logs/dic.log" subset > "$OUT/dic_bench.csv"
  step dic-sample15 "$BENCH_DIR/dic_sample15" "$ROOT/tests/data/dic"
  to_csv "$OUT/logs/dic-sample15.log" image > "$OUT/dic_sample15.csv"
  # shape as a number (1 first, 2 second) for gnuplot
  pick "$OUT/dic_bench.csv" "subset;shape;threads;points_per_s;rms_u_px;per_cpu_s" |
    awk '{ $2 = ($2 == "first" ? 1 : 2); printf "%s %s %s %.4f %s %s\n", $1, $2, $3, 1e6 / $4, $5, $6 }' |
    sort -k2,2n -k3,3n -k1,1n > "$OUT/dic_bench.dat"  # one series after the other
  cat > "$OUT/dic_bench.gp" << EOF
$GP_HEAD
set output 'dic_bench.png'
set title 'DIC (IC-GN), Sample 14 L1: time per point against RMS error of u'
set xlabel 'wall time per point [us]'
set ylabel 'RMS(u - exact) [px]'
plot for [s=1:2] for [t=1:2] 'dic_bench.dat' using 4:((\$2 == s && \$3 == t) ? \$5 : 1/0) \\
       with linespoints pt (s == 1 ? 7 : 5) lw 2 dt t \\
       title sprintf('%s order, %d thread(s)', s == 1 ? 'first' : 'second', t), \\
     '' using 4:((\$3 == 1) ? \$5 : 1/0):(sprintf('%sx%s', stringcolumn(1), stringcolumn(1))) \\
       with labels offset 1,0.8 left notitle
EOF
  plot dic_bench.gp
  ROWS+=$(awk '{ printf "| DIC | %sx%s, %s order, %s thread(s) | %s us per point | %s px RMS(u) |\n", $1, $1, ($2 == 1 ? "first" : "second"), $3, $4, $5 }' \
    "$OUT/dic_bench.dat")$'\n'
fi

# ---------------------------------------------------------------- optimizers
if wants fit; then
  # bf_inverse_bench writes fit_bench.csv, fit_bench_plot.dat, fit_bench.gp and fit_bench.png.
  step fit "$BENCH_DIR/bf_inverse_bench" "$OUT/fit_bench" "$FIT_H"
  ROWS+=$(pick "$OUT/fit_bench.csv" "case;optimizer;profile;cpu [s];max relative error" |
    awk '$3 == "no" { printf "| fit (%s) | %s | %s CPU s | %s (largest relative error) |\n", $1, $2, $4, $5 }')$'\n'
  # The load-displacement fit (docs/FIT.md): sigma_c error over noise draws per element size.
  step fit_load "$BENCH_DIR/bf_fit_load_bench" "$OUT/fit_load_bench" "$LOAD_FIT_DRAWS" "$LOAD_FIT_H"
  ROWS+=$(pick "$OUT/fit_load_bench_summary.csv" "elements [mm];mean cpu [s];max abs error [%];noise-free error [%]" |
    awk '{ printf "| load-displacement fit (truncated MDF) | %s mm | %s CPU s | %s%% (largest sigma_c error over the draws; %s%% without noise) |\n", $1, $2, $3, $4 }')$'\n'
fi

# ---------------------------------------------------------------- summary.md
T_END=$(date +%s)
{
  echo "# Speed versus accuracy: one run of bench/run_all.sh"
  echo
  echo "- command: \`$COMMAND_LINE\`$([[ $QUICK == 1 ]] && echo ' (QUICK smoke run: coarse settings, not for the README)')"
  echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC'), total $((T_END - T_START)) s"
  echo "- source: $(git -C "$ROOT" rev-parse --short HEAD 2> /dev/null || echo unknown)$(git -C "$ROOT" diff --quiet 2> /dev/null || echo ' (with uncommitted changes)')"
  echo "- build: $BUILD, $(grep -m1 CMAKE_BUILD_TYPE:STRING "$BUILD/CMakeCache.txt" 2> /dev/null | cut -d= -f2), $(c++ --version 2> /dev/null | head -1)"
  echo "- settings: reduced h = $REDUCED_H mm; MPM cells $MPM_CELLS mm, threads $MPM_THREADS; DIC subsets $DIC_SUBSETS px, step $DIC_STEP, threads $DIC_THREADS; fits at $FIT_H mm elements"
  echo "- machine: \`nproc\` = $(nproc); \`lscpu | head\`:"
  echo
  echo '```'
  lscpu | head -n 15
  echo '```'
  echo
  echo "Wall time and load average (1, 5, 15 min) around each step; with more"
  echo "runnable processes than cores, wall times are upper bounds (CPU seconds are given where the bench measures them):"
  echo
  echo "| step | wall [s] | load before | load after | exit |"
  echo "|---|---|---|---|---|"
  printf '%s' "$STEPS"
  echo
  echo "## Every point of the charts"
  echo
  echo "| bench | setting | time | error |"
  echo "|---|---|---|---|"
  printf '%s' "$ROWS"
  if wants reduced; then
    echo
    echo "## Reduced model ([reduced_bench.csv](reduced_bench.csv))"
    echo
    echo "![reduced model](reduced_bench.png)"
    echo
    md_table "$OUT/reduced_bench.csv" "resolution [mm];dofs;build [s];R curve median [ms];crack lengths;max error R [%];max error R-J_tip_c [%]"
  fi
  if wants mpm; then
    echo
    echo "## MPM, stationary crack ([mpm_bench.csv](mpm_bench.csv))"
    echo
    echo "![MPM](mpm_bench.png)"
    echo
    md_table "$OUT/mpm_bench.csv" "cell_mm;threads;particles;steps;wall_s;cpu_s;Mparticle_steps_per_s;J_err_pct;C_err_pct"
    echo
    echo "## MPM with crack growth: R curve against the reduced model ([mpm_growth_bench.csv](mpm_growth_bench.csv))"
    echo
    cat "$OUT/mpm_growth.md"
  fi
  if wants dic; then
    echo
    echo "## DIC ([dic_bench.csv](dic_bench.csv), [dic_sample15.csv](dic_sample15.csv))"
    echo
    echo "![DIC](dic_bench.png)"
    echo
    md_table "$OUT/dic_bench.csv" "subset;shape;threads;points;wall_s;points_per_s;per_cpu_s;rms_u_px"
    echo
    echo "Subset size against the smearing of a displacement step (Sample 15, no timing):"
    echo
    md_table "$OUT/dic_sample15.csv" "image;subset;shape;rms_v_px;max_px;points"
  fi
  if wants fit; then
    echo
    echo "## Optimizers ([fit_bench.csv](fit_bench.csv))"
    echo
    echo "![optimizers](fit_bench.png)"
    echo
    echo "Error: the largest relative error of the parameters the case identifies; inf: a wrong"
    echo "verdict (bridging missed or invented, or a J_B bound above the truth), not drawn."
    echo
    md_table "$OUT/fit_bench.csv" "case;optimizer;profile;evaluations;failed;wall [s];cpu [s];max relative error;converged"
    echo
    echo "## Load-displacement fit ([fit_load_bench_summary.csv](fit_load_bench_summary.csv), [per draw](fit_load_bench.csv))"
    echo
    echo "![load-displacement fit](fit_load_bench.png)"
    echo
    echo "Truncated MDF test (0.45 MPa, 500, 2210 to a = 70 mm), records from the reduced model at"
    echo "0.0625 mm with 0.5% load noise, fitted at each element size; sigma_c error in %."
    echo
    md_table "$OUT/fit_load_bench_summary.csv" "elements [mm];draws;max abs error [%];mean error [%];sd [%];within 3%;within 5%;ci covers;mean cpu [s];noise-free error [%]"
  fi
} > "$OUT/summary.md"
echo "written: $OUT/summary.md ($((T_END - T_START)) s)" >&2
