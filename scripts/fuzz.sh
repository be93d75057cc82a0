#!/usr/bin/env bash
# fuzz.sh - builds the libFuzzer targets (fuzz/fuzz_*.c) with clang, ASan and UBSan, and runs
# each for a bounded time from its seed corpus.
# Usage: scripts/fuzz.sh [BUILD_DIR [TARGET...]]      (default build-fuzz, every target)
# Environment: FUZZ_SECONDS per target (60), FUZZ_JOBS targets at a time (nproc),
#              FUZZ_MAX_LEN longest input in bytes (4096), FUZZ_SEED libFuzzer's seed (CI: 1,
#              so that CI explores the same inputs every run and a finding can be replayed;
#              otherwise 0, a new seed every run, for exploring by hand).
#
# The corpus grows in BUILD_DIR/corpus/NAME (seeded from fuzz/corpus/NAME, never written back).
# A crash is kept in BUILD_DIR/crashes/NAME/ and fails the run. To make it a regression test:
# minimise it (BUILD_DIR/fuzz_NAME -minimize_crash=1 CRASH), fix the bug, and copy the input to
# fuzz/regressions/NAME/, which ctest replays in every build (fuzz_replay_NAME).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-fuzz}
shift || true
seconds=${FUZZ_SECONDS:-60}
jobs=${FUZZ_JOBS:-$(nproc)}
max_len=${FUZZ_MAX_LEN:-4096}
if [[ "${CI:-}" == true ]]; then seed=${FUZZ_SEED:-1}; else seed=${FUZZ_SEED:-0}; fi

if (($# > 0)); then
    names=("$@")
else
    names=()
    for source in fuzz/fuzz_*.c; do
        name=${source#fuzz/fuzz_}
        names+=("${name%.c}")
    done
fi

if ! command -v clang >/dev/null; then
    echo "fuzz: clang is not installed (scripts/install-deps.sh installs it)" >&2
    exit 1
fi
cmake -S . -B "$build" -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
      -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRAD_FUZZ=ON -DRAD_NATIVE=OFF >/dev/null
targets=()
for name in "${names[@]}"; do targets+=("fuzz_$name"); done
cmake --build "$build" -j "$(nproc)" --target "${targets[@]}"

export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"

run_one() { # run_one NAME: fuzz one target; output to BUILD/logs/NAME.log
    local name=$1
    local corpus=$build/corpus/$name crashes=$build/crashes/$name
    mkdir -p "$corpus" "$crashes" "$build/logs"
    # fuzz/fuzz_NAME.options: extra libFuzzer flags for one target, and ASAN_OPTIONS=... lines
    # appended to ASan's options (later ones win); '#' starts a comment.
    local extra=() asan=$ASAN_OPTIONS
    if [[ -f fuzz/fuzz_$name.options ]]; then
        read -ra extra <<<"$(grep '^-' "fuzz/fuzz_$name.options" | tr '\n' ' ')"
        local line
        while read -r line; do asan+=":${line#ASAN_OPTIONS=}"; done \
            < <(grep '^ASAN_OPTIONS=' "fuzz/fuzz_$name.options")
    fi
    ASAN_OPTIONS=$asan "$build/fuzz_$name" "${extra[@]}" -max_total_time="$seconds" \
        -max_len="$max_len" -timeout=10 -seed="$seed" \
        -rss_limit_mb=2048 -close_fd_mask=3 -print_final_stats=1 -artifact_prefix="$crashes/" \
        "$corpus" "fuzz/corpus/$name" >"$build/logs/$name.log" 2>&1
}

failed=()
pids=() running=()
finish_one() { # waits for the oldest running target and reports it
    local pid=${pids[0]} name=${running[0]}
    pids=("${pids[@]:1}") running=("${running[@]:1}")
    if wait "$pid"; then
        local runs
        runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$build/logs/$name.log" |
               grep -o '[0-9]*$' || echo '?')
        echo "fuzz: $name: no crash in ${seconds}s ($runs inputs)"
    else
        echo "fuzz: $name: FAILED; log $build/logs/$name.log, inputs in $build/crashes/$name/" >&2
        grep -E 'ERROR|SUMMARY|runtime error|Test unit written' "$build/logs/$name.log" | head -n 8 >&2
        failed+=("$name")
    fi
}
for name in "${names[@]}"; do
    if [[ ! -d fuzz/corpus/$name ]]; then
        echo "fuzz: no seed corpus fuzz/corpus/$name" >&2
        exit 1
    fi
    run_one "$name" &
    pids+=($!) running+=("$name")
    ((${#pids[@]} >= jobs)) && finish_one
done
while ((${#pids[@]} > 0)); do finish_one; done

echo "$((${#names[@]} - ${#failed[@]})) passed, ${#failed[@]} failed"
((${#failed[@]} == 0))
