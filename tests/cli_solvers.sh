#!/usr/bin/env bash
# cli_solvers.sh - `radiosity solvers` prints the registries, and the lists the commands show
# (help, unknown-name errors) are the registries' names.
# Usage: cli_solvers.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"

"$radiosity" solvers >"$work/list"
check "solvers exits 0" test $? -eq 0
solvers="direct jacobi gauss-seidel shooting importance hierarchical"
methods="analytic hemicube raycast montecarlo"
for name in $solvers $methods; do
    check "solvers lists $name" grep -q "^  $name " "$work/list"
done
check "the default solver is marked" grep -q "^  shooting .*(default)$" "$work/list"
check "the default method is marked" grep -q "^  analytic .*(default)$" "$work/list"
check "shooting's own options" grep -q -- "--overshoot" "$work/list"

expect_exit 2 "unknown solver 'bogus' (direct, jacobi, gauss-seidel, shooting, importance, hierarchical)" -- \
    "$radiosity" solve four-walls --solver bogus
expect_exit 2 "unknown form-factor method 'bogus' (analytic, hemicube, raycast, montecarlo)" -- \
    "$radiosity" render cornell --ff bogus
expect_exit 2 "overshoot is for the shooting and importance solvers" -- \
    "$radiosity" solve four-walls --solver jacobi --overshoot
"$radiosity" solve --help >"$work/help"
check "solve --help lists the solvers" \
    grep -q -- "--solver .*NAME  direct|jacobi|gauss-seidel|shooting|importance|hierarchical (shooting; hierarchical for scenes of 8000 polygons or more)" "$work/help"
"$radiosity" render --help >"$work/help"
check "render's default is shooting, as solve's" grep -q -- "hierarchical (shooting; hierarchical for scenes of 8000 polygons or more)" "$work/help"
check "--ff lists the methods" grep -q -- "METHOD  analytic|hemicube|raycast|montecarlo" "$work/help"
expect_exit 2 "unexpected argument" -- "$radiosity" solvers extra
finish
