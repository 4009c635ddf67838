#!/usr/bin/env bash
# Builds the libFuzzer harnesses (clang-14, ASan + UBSan) into build-fuzz/ and
# runs each for SECONDS (default 60), one after the other, with seed corpora
# from tests/data and the regression inputs. Usage: scripts/fuzz.sh [SECONDS]
# Writes a summary per harness to build-fuzz/fuzz-summary.txt; any crash,
# sanitizer report or leak leaves its input in build-fuzz/artifacts/ and makes
# the script exit 1. Record figures in docs/HOSTILE_INPUT.md.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
root=$(pwd)
build=build-fuzz
CC=${CC:-clang-14}
CXX=${CXX:-clang++-14}
mkdir -p "$build"
launcher=()
command -v ccache > /dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER="$CC" \
  -DCMAKE_CXX_COMPILER="$CXX" -DBRIDGEFIT_FUZZ=ON -DBRIDGEFIT_BUILD_TESTS=OFF "${launcher[@]}" \
  > "$build/build.log" 2>&1 || { tail -n 40 "$build/build.log"; exit 1; }
# FUZZ_HARNESSES="ncorr fields" runs only those.
read -r -a harnesses <<< "${FUZZ_HARNESSES:-units csv scene h5 image fields ncorr}"
targets=()
for h in "${harnesses[@]}"; do targets+=("fuzz_$h"); done
cmake --build "$build" -j"$(nproc)" --target "${targets[@]}" make_ncorr_seeds >> "$build/build.log" 2>&1 \
  || { tail -n 60 "$build/build.log"; exit 1; }

# Seed corpora: the repository's own inputs of each kind.
seeds=$build/seeds
rm -rf "$seeds"
mkdir -p "$seeds"/{units,csv,scene,h5,image,fields,ncorr}
"$build/tests/fuzz/make_ncorr_seeds" "$seeds/ncorr"
printf '%s\n' "MPa" "J/m^2" "kg/m^3" "N/mm" "mm/px" "m.s^-1" "0.45 MPa" "2 m^2*s^-2" "1 kN*mm" \
  "12.7 mm" "500 kJ/m^2" | split -l 1 - "$seeds/units/u"
cp tests/data/experiment/*.csv tests/data/scenes/*.csv "$seeds/csv/" 2>/dev/null || true
find data_samples -name '*.csv' -size -200k -exec cp {} "$seeds/csv/" \; 2>/dev/null || true
cp tests/data/scenes/*.toml tests/data/models/*.toml tests/data/mpm/*.toml "$seeds/scene/"
cp tests/fuzz/seeds/h5/*.h5 "$seeds/h5/"
find tests/data/dic data_samples \( -name '*.png' -o -name '*.tif' -o -name '*.bmp' \) -size -300k \
  2>/dev/null | head -n 20 | while read -r f; do cp "$f" "$seeds/image/"; done
find tests/data/fields -type f ! -name '*.md' -size -200k -exec cp {} "$seeds/fields/" \;
for kind in "${harnesses[@]}"; do
  [[ -d tests/fuzz/regressions/$kind ]] && cp tests/fuzz/regressions/"$kind"/* "$seeds/$kind/" 2>/dev/null || true
done
mkdir -p "$build/artifacts" "$build/corpus"
summary=$build/fuzz-summary.txt
: > "$summary"
status=0
# Allocations over 512 MiB fail (return null) as they do under the CLI's
# address-space limit for the HDF5 checking child, instead of stalling.
export ASAN_OPTIONS=${ASAN_OPTIONS:-halt_on_error=1:detect_leaks=1:allocator_may_return_null=1:max_allocation_size_mb=512}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
# Leaks inside third-party libraries (libhdf5's error paths on a corrupt
# file read through matio) are not bridgefit's: the sanitizer suite's list.
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$root/scripts/sanitize.supp:print_suppressions=0}
run_one() {
  local h=$1 corpus=$build/corpus/$1 log=$build/fuzz_$1.log rc
  mkdir -p "$corpus"
  local dict=()
  [[ -f tests/fuzz/$h.dict ]] && dict=(-dict="tests/fuzz/$h.dict")
  echo "fuzz.sh: $h for $seconds s"
  set +e
  "$build/tests/fuzz/fuzz_$h" "$corpus" "$seeds/$h" "${dict[@]}" -max_total_time="$seconds" \
    -max_len=65536 -timeout=30 -rss_limit_mb=4096 -print_final_stats=1 \
    -artifact_prefix="$build/artifacts/${h}-" > "$log" 2>&1
  rc=$?
  set -e
  local execs cov ft units
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 | grep -o '[0-9]*' || echo "?")
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -n 1 | grep -o '[0-9]*' || echo "?")
  units=$(ls "$corpus" | wc -l)
  echo "$h: exit $rc, $execs executions in $seconds s, coverage $cov edges, $ft features, corpus $units inputs" > "$build/fuzz_$h.summary"
  [[ $rc -ne 0 ]] && grep -E "ERROR|SUMMARY|runtime error" "$log" | head -n 5 >> "$build/fuzz_$h.summary"
  return $rc
}
# FUZZ_PARALLEL=1 runs all harnesses at once (each still SECONDS of wall time).
pids=()
for h in "${harnesses[@]}"; do
  if [[ "${FUZZ_PARALLEL:-0}" == 1 ]]; then
    run_one "$h" & pids+=($!)
  else
    run_one "$h" || status=1
  fi
done
for pid in "${pids[@]}"; do wait "$pid" || status=1; done
for h in "${harnesses[@]}"; do cat "$build/fuzz_$h.summary"; done | tee "$summary"
echo "fuzz.sh: summary in $summary"
exit $status
