#!/usr/bin/env bash
# cli_batch.sh - feedback when stderr is not a terminal (a batch job, a log file): one
# "radiosity: [STAGE] ..." line per stage of solve, render, bake and pathtrace, none with
# --quiet; render and bake solve as solve does (shooting by default), take --time-budget, and
# bake takes a saved --solution.
# Usage: cli_batch.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"
cd "$work" || exit 1

"$radiosity" solve cornell --elements 300 >out 2>err
check "solve exits 0" test $? -eq 0
check "solve: scene line" grep -Eq '^radiosity: \[scene\] cornell \(built in\), [0-9.]+ s$' err
check "solve: mesh line with the element count" \
    grep -Eq '^radiosity: \[mesh\] 8 surfaces, [0-9]+ patches, [0-9]+ elements, [0-9.]+ s$' err
check "solve: solve line" \
    grep -Eq '^radiosity: \[solve\] shooting, [0-9]+ shots, residual [0-9.e+-]+, converged, [0-9.]+ s$' err

"$radiosity" solve cornell --elements 300 --quiet >out 2>err
check "--quiet: no stage lines" test ! -s err

"$radiosity" render cornell -o r.png --width 16 --height 16 --spp 1 --elements 300 >out 2>err
check "render exits 0" test $? -eq 0
check "render solves with shooting, as solve does" grep -q '^radiosity: \[solve\] shooting, ' err
check "render: render line" \
    grep -Eq '^radiosity: \[render\] 16x16 pixels, 1 samples per pixel, final gather 4, smooth shading$' err
# Progress lines ("... (5 s so far)", printed when a stage runs past 5 s, as under load) may come
# between the stages; the stage lines alone keep their order.
check "stage order" test "$(grep -v 'so far)$' err | grep -oE '^radiosity: \[[a-z]+\]' | tr '\n' ' ')" = \
    "radiosity: [scene] radiosity: [mesh] radiosity: [solve] radiosity: [render] "
check "render: nothing on stdout" test ! -s out

# --time-budget stops the solve (a tolerance that is never reached) and still renders.
"$radiosity" render cornell -o t.png --width 16 --height 16 --spp 1 --elements 2000 \
    --tolerance 1e-300 --time-budget 0.3 >out 2>err
check "render --time-budget exits 0" test $? -eq 0
check "render --time-budget stopped the solve" grep -q '^radiosity: \[solve\] shooting, .*not converged' err
check "render --time-budget wrote the image" test -s t.png
expect_exit 2 'time-budget must be a positive' -- "$radiosity" render cornell --time-budget -1

# bake: the default solver and a saved solution.
"$radiosity" bake cornell -o a.ply --elements 300 >out 2>err
check "bake solves with shooting" grep -q '^radiosity: \[solve\] shooting, ' err
check "bake: bake line" grep -q '^radiosity: \[bake\] a.ply$' err
# The element count on stderr is the one bake reports on stdout.
elements=$(grep -oE '[0-9]+ elements' err | grep -oE '[0-9]+')
check "mesh line's count is the real one" grep -q "^baked $elements elements" out
"$radiosity" solve cornell --elements 300 --save c.sol --quiet >/dev/null
"$radiosity" bake cornell -o b.ply --elements 300 --solution c.sol >out 2>err
check "bake --solution exits 0" test $? -eq 0
check "bake --solution loaded it" grep -q '^radiosity: \[solve\] loaded from c.sol$' err
check "bake --solution says so" grep -q 'solution from c.sol' out
check "bake --solution: no solve" test "$(grep -c 'shots' err)" -eq 0
expect_exit 1 'c.sol' -- "$radiosity" bake cornell -o c.ply --elements 900 --solution c.sol
check "a refused solution leaves no file" test ! -e c.ply
expect_exit 2 'time-budget' -- "$radiosity" bake cornell -o d.ply --time-budget -2

"$radiosity" pathtrace -o p.pfm --width 8 --height 8 --spp 2 >out 2>err
check "pathtrace: stage lines" test "$(grep -oE '^radiosity: \[[a-z]+\]' err | tr '\n' ' ')" = \
    "radiosity: [scene] radiosity: [pathtrace] "
check "pathtrace: its size and samples" grep -q '^radiosity: \[pathtrace\] 8x8 pixels, 2 paths per pixel$' err

finish
