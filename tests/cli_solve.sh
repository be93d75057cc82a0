#!/usr/bin/env bash
# cli_solve.sh - `radiosity solve`, `scenes`, --help, --version: output, JSON, exit statuses.
# Usage: cli_solve.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"

# Help and version.
"$radiosity" --version | grep -q '^radiosity [0-9]' ; check version test $? -eq 0
"$radiosity" --help | grep -q 'solve' ; check help test $? -eq 0
"$radiosity" solve --help | grep -q -- '--solver' ; check "solve --help" test $? -eq 0
"$radiosity" scenes | grep -q '^four-walls' ; check scenes test $? -eq 0

# The table and JSON of the four-surface room.
"$radiosity" solve four-walls --solver direct >"$work/table"
check "table has the window" grep -Eq '^right +1 +1\.003050' "$work/table"
"$radiosity" solve "$source_dir/scenes/four-walls.ffm" --solver gauss-seidel --tolerance 1e-9 >"$work/file"
check "file equals built-in" grep -Eq '^right +1 +1\.003050' "$work/file"
"$radiosity" solve four-walls --solver jacobi --iterations 2 --json >"$work/json"
check "json solver" grep -q '"solver": "jacobi", "iterations": 2, "converged": false' "$work/json"
check "json patch" grep -q '{"name": "floor", "area": 1, "radiosity": \[0.04375' "$work/json"
"$radiosity" solve four-walls --solver shooting --iterations 1 --json --trace >"$work/trace"
check "json trace shooter" grep -q '"shooter": "right"' "$work/trace"
check "json trace unshot" grep -q '"unshot": {"ceiling": \[0.1875' "$work/trace"
"$radiosity" solve four-walls --solver jacobi --iterations 2 --trace >"$work/text"
check "text trace round 2" grep -Eq '^  floor +received 0.4375 +radiosity 0.04375' "$work/text"

# Usage errors: exit 2.
expect_exit 2 'unknown solver' -- "$radiosity" solve four-walls --solver magic
expect_exit 2 'unknown option' -- "$radiosity" solve four-walls --frobnicate
expect_exit 2 'needs a value' -- "$radiosity" solve four-walls --iterations
expect_exit 2 'whole number' -- "$radiosity" solve four-walls --iterations -3
expect_exit 2 'wants a number' -- "$radiosity" solve four-walls --tolerance abc
expect_exit 2 'which scene' -- "$radiosity" solve
expect_exit 2 'unknown command' -- "$radiosity" frobnicate

# Errors: exit 1, one line naming the file and line.
expect_exit 1 'missing.ffm' -- "$radiosity" solve "$work/missing.ffm"
printf 'patch a area 1 reflectance 2 emission 1\n' >"$work/bad.ffm"
expect_exit 1 'bad.ffm:1: reflectance' -- "$radiosity" solve "$work/bad.ffm"
: >"$work/empty.ffm"
expect_exit 1 'empty file' -- "$radiosity" solve "$work/empty.ffm"
head -c 300 /dev/urandom >"$work/garbage.ffm"
"$radiosity" solve "$work/garbage.ffm" >/dev/null 2>&1
check "garbage exits 1" test $? -eq 1
expect_exit 2 'omega' -- "$radiosity" solve four-walls --omega 2.5
printf 'patch a area 1 reflectance 0.5\n' >"$work/dark.ffm"
"$radiosity" solve "$work/dark.ffm" >"$work/out" 2>"$work/err"
check "no emitter is a warning" test $? -eq 0
check "no emitter warns" grep -q 'nothing emits' "$work/err"

finish
