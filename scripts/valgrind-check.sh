#!/usr/bin/env bash
# valgrind-check.sh - a short solve, render, path trace, compare and bake under valgrind
# memcheck: no errors and no leaks (definite, indirect or possible).
# Usage: scripts/valgrind-check.sh [BUILD_DIR]       (default build-valgrind)
#
# Builds the CLI without -march=native (valgrind does not know AVX-512) and with debug info.
# scripts/valgrind.supp holds only the thread-local storage of the OpenMP and TBB worker
# threads that still exist at exit.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-valgrind}
if ! command -v valgrind >/dev/null; then
    echo "valgrind-check: valgrind is not installed (scripts/install-deps.sh installs it)" >&2
    exit 1
fi
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRAD_NATIVE=OFF >/dev/null
cmake --build "$build" -j "$(nproc)" --target radiosity_cli
radiosity=$(cd "$build" && pwd)/radiosity
supp=$(pwd)/scripts/valgrind.supp
source=$(pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

passed=0 failed=0
memcheck() { # memcheck NAME EXIT ARGS...: `radiosity ARGS` under memcheck must exit with EXIT
    local name=$1 want=$2; shift 2
    local got=0
    valgrind -q --error-exitcode=99 --leak-check=full \
        --show-leak-kinds=definite,indirect,possible \
        --errors-for-leak-kinds=definite,indirect,possible --track-origins=yes \
        --suppressions="$supp" --log-file="$work/$name.log" \
        "$radiosity" "$@" >"$work/$name.out" 2>"$work/$name.err" || got=$?
    if [[ $got == "$want" && ! -s $work/$name.log ]]; then
        passed=$((passed + 1))
        echo "valgrind-check: $name: clean"
    else
        failed=$((failed + 1))
        echo "valgrind-check: $name: FAILED with exit $got, not $want (radiosity $*)" >&2
        cat "$work/$name.err" "$work/$name.log" | head -n 80 >&2
    fi
}

source_dir=$(pwd)
cd "$work"
memcheck solve-ffm 0 solve four-walls --solver direct --json
memcheck solve-cornell 0 solve cornell --elements 150 --solver shooting --threads 2 --quiet
memcheck render 0 render cornell --elements 150 --width 24 --height 24 --spp 1 --threads 2 \
    --quiet -o render.pfm
memcheck pathtrace 0 pathtrace cornell --width 24 --height 24 --spp 2 --threads 2 --quiet \
    -o pathtrace.pfm
memcheck compare 0 compare render.pfm pathtrace.pfm --diff diff.png
# The room at 1500 elements flushes packets with lanes left over: before every lane was filled,
# memcheck saw uninitialised lanes reach rtcOccluded16 (the Embree assertion of issue 13).
memcheck packet-lanes 0 solve "$source/scenes/room.obj" --elements 1500 --tolerance 0.05 \
    --threads 1 --quiet
memcheck bake 0 bake unit-cube --elements 24 --threads 2 --quiet -o cube.ply
# An imported scene: the import runs in a forked child, which memcheck follows (no
# --trace-children needed for a fork); the child leaves with _exit, so only the parent's
# memory is checked for leaks at its exit, and the child's own errors still show.
memcheck import 0 solve "$source_dir/tests/assimp-sample/ok-Cube.off" --elements 24 --threads 2 --quiet
memcheck hierarchical 0 solve cornell --elements 150 --solver hierarchical --threads 2 --quiet
memcheck missing-file 1 solve missing.ffm
printf 'patch a area 1 reflectance 0.5 emission 1\nff a b 0.5\n' >bad.ffm
memcheck parse-error 1 solve bad.ffm

echo "$passed passed, $failed failed"
((failed == 0))
