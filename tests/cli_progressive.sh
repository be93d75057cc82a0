#!/usr/bin/env bash
# cli_progressive.sh - watching `radiosity solve` converge and stopping it: --log, --plot,
# --time-budget, --save/--resume (same result as never stopping), --snapshots, --overshoot,
# --solver importance, --compare-solvers, and bad input (one line, exit 1 or 2, nothing lost).
# Usage: cli_progressive.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"

# The radiosity column of the table, for comparing runs.
table() { grep -E '^[a-z-]+ +[0-9]' "$1"; }

small=(cornell --elements 300 --quiet)
close=(--eye 186,200,-100 --look 186,80,170 --fov 30)

# --log and --plot.
"$radiosity" solve "${small[@]}" --log "$work/run.csv" --plot "$work/run.svg" --tolerance 1e-3 >"$work/out"
check "log and plot run" test $? -eq 0
check "log header" test "$(head -1 "$work/run.csv")" = "iteration,seconds,shots,sweeps,unshot_fraction,residual"
check "log has a row per shot" test "$(($(wc -l <"$work/run.csv") - 1))" -eq "$(grep -oE '[0-9]+ shots' "$work/out" | grep -oE '[0-9]+')"
check "log row" grep -Eq '^1,[0-9.]+,1,0,0\.[0-9]+,0\.[0-9]+$' "$work/run.csv"
check "plot is svg" grep -q '<svg' "$work/run.svg"
check "plot has a line" grep -q '<polyline' "$work/run.svg"
"$radiosity" solve four-walls --solver jacobi --log "$work/jacobi.csv" --quiet >/dev/null
check "gathering rows: sweeps, no unshot" grep -Eq '^2,[0-9.]+,0,2,,0\.[0-9]+' "$work/jacobi.csv"

# --time-budget: stops with the solution so far, not an error.
"$radiosity" solve "${small[@]}" --tolerance 1e-12 --time-budget 1e-6 >"$work/out"
check "time budget exit 0" test $? -eq 0
check "time budget says so" grep -q '^shooting: 1 shot, not converged: time budget of 1e-06 s used up' "$work/out"

# --save then --resume: the same numbers as one run.
"$radiosity" solve "${small[@]}" --overshoot --iterations 70 >"$work/straight"
"$radiosity" solve "${small[@]}" --overshoot --iterations 30 --save "$work/part.sol" >/dev/null
check "saved" test -s "$work/part.sol"
"$radiosity" solve "${small[@]}" --overshoot --iterations 40 --resume "$work/part.sol" >"$work/resumed"
check "resumed counts on" grep -q '^shooting: 70 shots' "$work/resumed"
check "resumed equals straight" diff <(table "$work/straight") <(table "$work/resumed")
"$radiosity" solve "${small[@]}" --iterations 10 --resume "$work/part.sol" --log "$work/more.csv" >/dev/null
check "log numbers go on" grep -q '^31,' "$work/more.csv"
# Resuming with the solver of the file when none is given; a gathering file cannot go on shooting.
"$radiosity" solve four-walls --solver jacobi --iterations 3 --save "$work/jacobi.sol" --quiet >/dev/null
"$radiosity" solve four-walls --resume "$work/jacobi.sol" --quiet >"$work/out"
check "resume takes the file's solver" grep -q '^jacobi: 11 rounds, converged' "$work/out"
expect_exit 2 'unshot light is unknown' -- "$radiosity" solve four-walls --resume "$work/jacobi.sol" --solver shooting

# Bad resume files: one line, exit 1, the file itself untouched.
cp "$work/part.sol" "$work/keep.sol"
head -c 1000 "$work/part.sol" >"$work/short.sol"
expect_exit 1 'truncated' -- "$radiosity" solve "${small[@]}" --resume "$work/short.sol"
cp "$work/part.sol" "$work/flip.sol"
printf '\x55' | dd of="$work/flip.sol" bs=1 seek=500 conv=notrunc 2>/dev/null
expect_exit 1 'checksum' -- "$radiosity" solve "${small[@]}" --resume "$work/flip.sol"
expect_exit 1 'not a radiosity solution file' -- "$radiosity" solve "${small[@]}" --resume "$work/run.csv"
expect_exit 1 'different scene' -- "$radiosity" solve unit-cube --elements 300 --resume "$work/part.sol"
expect_exit 1 'different mesh' -- "$radiosity" solve cornell --elements 500 --resume "$work/part.sol"
expect_exit 1 'cannot read' -- "$radiosity" solve "${small[@]}" --resume "$work/none.sol"
check "resume file untouched" cmp -s "$work/part.sol" "$work/keep.sol"
# A failed run leaves the --save target as it was.
expect_exit 1 'different mesh' -- "$radiosity" solve cornell --elements 500 --resume "$work/part.sol" --save "$work/part.sol"
check "save target untouched" cmp -s "$work/part.sol" "$work/keep.sol"

# Usage errors: exit 2.
expect_exit 2 'time-budget must be a positive' -- "$radiosity" solve four-walls --time-budget 0
expect_exit 2 'time-budget must be a positive' -- "$radiosity" solve four-walls --time-budget -3
expect_exit 2 'needs --snapshots' -- "$radiosity" solve four-walls --snapshot-every 5
expect_exit 2 'overshoot is for' -- "$radiosity" solve four-walls --solver jacobi --overshoot
expect_exit 2 'unknown solver' -- "$radiosity" solve four-walls --solver importants
# Outputs that cannot be written fail before any work.
touch "$work/file"
expect_exit 1 'not a directory' -- "$radiosity" solve "${small[@]}" --snapshots "$work/file"
expect_exit 1 'snapshots-missing' -- "$radiosity" solve "${small[@]}" --snapshots "$work/snapshots-missing"
expect_exit 1 'cannot write' -- "$radiosity" solve "${small[@]}" --save "$work/missing-dir/a.sol"
expect_exit 1 'cannot write' -- "$radiosity" solve "${small[@]}" --log "$work/missing-dir/a.csv"
expect_exit 1 'is a directory' -- "$radiosity" solve "${small[@]}" --plot "$work"

# Snapshots: an image every K shots, and the last one.
mkdir "$work/snaps"
"$radiosity" solve "${small[@]}" --snapshots "$work/snaps" --snapshot-every 20 --iterations 50 --width 32 --height 24 >/dev/null
check "snapshots exit 0" test $? -eq 0
check "snapshot 20" test -s "$work/snaps/snapshot-000020.png"
check "snapshot 40" test -s "$work/snaps/snapshot-000040.png"
check "final snapshot" test -s "$work/snaps/snapshot-000050.png"
check "three snapshots" test "$(ls "$work/snaps" | wc -l)" -eq 3

# Importance: needs geometry; converges to the same solution as shooting.
expect_exit 1 'geometric scene' -- "$radiosity" solve four-walls --solver importance
"$radiosity" solve "${small[@]}" --solver importance "${close[@]}" --tolerance 1e-9 >"$work/imp"
"$radiosity" solve "${small[@]}" --solver shooting --tolerance 1e-9 >"$work/shoot"
check "importance converges" grep -q '^importance: [0-9]* shots, converged' "$work/imp"
check "importance = shooting" diff <(table "$work/imp" | cut -c1-80) <(table "$work/shoot" | cut -c1-80)

# The comparison: every solver on one chart.
"$radiosity" solve "${small[@]}" --compare-solvers "${close[@]}" --plot "$work/compare.svg" --log "$work/compare.csv" >"$work/out"
check "compare exit 0" test $? -eq 0
for solver in jacobi gauss-seidel 'SOR, omega 1.1' shooting overshooting importance hierarchical; do
    check "compare row $solver" grep -q "^$solver " "$work/out"
    check "compare legend $solver" grep -q ">$solver</text>" "$work/compare.svg"
done
check "compare lines" test "$(grep -c "<polyline" "$work/compare.svg")" -eq 10
# The hierarchy (its own leaves) is measured against its own converged solution, so it reaches
# 1%; a line says how far that solution lies from the elements' reference.
check "compare: the hierarchy reaches 1% of its own solution" grep -Eq '^hierarchical +[0-9]+ steps?, ' "$work/out"
check "compare: says what the hierarchy is measured against" grep -Eq '^  \(hierarchical: against its own converged solution, [0-9]+ leaves at link error .*; that lies [0-9.e-]+ from the reference above' "$work/out"
check "compare log" grep -q '^importance,1,' "$work/compare.csv"
check "compare log quotes" grep -q '^"SOR, omega 1.1",1,' "$work/compare.csv"
"$radiosity" solve four-walls --compare-solvers --quiet >"$work/out"
check "compare without geometry: no importance" test "$(grep -c ' rounds\| shots\| steps\?,' "$work/out")" -eq 5

finish
