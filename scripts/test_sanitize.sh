#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer,
# halting on the first report (also: scripts/test.sh --sanitize).
# Builds into build-sanitize/ (GCC, RelWithDebInfo; CC/CXX to change). Any
# sanitizer report fails the test that triggered it, and so the script.
# Usage: scripts/test_sanitize.sh [ctest args, e.g. -R Units]
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
build=build-sanitize
jobs=$(nproc 2>/dev/null || echo 2)
mkdir -p "$build"
launcher=()
command -v ccache > /dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBRIDGEFIT_SANITIZE=ON "${launcher[@]}" \
  > "$build/build.log" 2>&1 || { tail -n 40 "$build/build.log"; exit 1; }
cmake --build "$build" -j"$jobs" >> "$build/build.log" 2>&1 || { tail -n 80 "$build/build.log"; exit 1; }
built=$(date +%s)
echo "test_sanitize: built in $(( built - start )) s"
# halt_on_error: the first report ends the process with a non-zero exit.
# Leaks are checked; the suppressions name third-party one-time allocations only.
export ASAN_OPTIONS="halt_on_error=1:abort_on_error=0:detect_leaks=1:detect_stack_use_after_return=0:strict_string_checks=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export LSAN_OPTIONS="suppressions=$(pwd)/scripts/sanitize.supp:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
# OpenMP threads under ASan are slow to start and stop; the suite is the same.
ctest --test-dir "$build" --output-on-failure -j"$jobs" --timeout 1800 "$@"
echo "test_sanitize: tests passed in $(( $(date +%s) - built )) s (total $(( $(date +%s) - start )) s)"
