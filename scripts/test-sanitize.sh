#!/usr/bin/env bash
# test-sanitize.sh - builds the project with AddressSanitizer and UndefinedBehaviorSanitizer
# (RAD_SANITIZE=ON, gcc by default) and runs the whole ctest suite there.
# Usage: scripts/test-sanitize.sh [BUILD_DIR]     (default build-sanitize)
#
# Every sanitizer report is written to BUILD_DIR/sanitizer-logs/ as well as ending its process
# with status 86, so a report from a process whose status a shell test does not look at (a
# pipeline, a leak found at exit) still fails the run. RAD_TEST_QUICK=1 asks the slowest tests
# for their reduced mode.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-sanitize}
jobs=${JOBS:-$(nproc)}

cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRAD_SANITIZE=ON -DRAD_NATIVE=OFF \
      >/dev/null
# What ctest runs: the tool, both libraries (the install test), every tests/test_*.c and every
# fuzz replay; not the benchmarks, which ctest never runs (the Release build compiles them).
targets=(radiosity_cli radiosity radiosity_shared)
for source in tests/test_*.c; do targets+=("$(basename "$source" .c)"); done
for source in fuzz/fuzz_*.c; do targets+=("$(basename "$source" .c)_replay"); done
cmake --build "$build" -j "$jobs" --target "${targets[@]}"

logs=$(cd "$build" && pwd)/sanitizer-logs
rm -rf "$logs"
mkdir -p "$logs"
export RAD_TEST_QUICK=1
export ASAN_OPTIONS="exitcode=86:log_path=$logs/asan:log_exe_name=1:detect_leaks=1:strict_string_checks=1:check_initialization_order=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="exitcode=86:log_path=$logs/ubsan:log_exe_name=1:print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$(pwd)/scripts/lsan.supp:print_suppressions=0"

status=0
(cd "$build" && ctest --output-on-failure -j "$jobs") || status=$?
if compgen -G "$logs/*" >/dev/null; then
    echo "test-sanitize: sanitizer reports:" >&2
    for report in "$logs"/*; do
        echo "---- $report" >&2
        head -n 60 "$report" >&2
    done
    status=1
fi
exit "$status"
