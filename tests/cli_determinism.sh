#!/usr/bin/env bash
# cli_determinism.sh - the same inputs and --seed give byte-identical outputs with --threads 1
# and --threads 2: `solve --json` (Monte Carlo form factors, every solver), `render` (random
# form factors and final gather), `pathtrace`, `bake` and `formfactors --json`. Each random choice draws from a stream derived
# from (seed, task), never from the thread that runs it. A different seed must change the
# randomised outputs (else the test could not fail).
# Usage: cli_determinism.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"

# The JSON's wall-clock time is the one field allowed to differ.
strip_time() { sed -E 's/"seconds": [0-9.eE+-]+/"seconds": _/g' "$1" >"$1.stripped"; }

# same_with_threads NAME OUTPUT-EXTENSION ARGS...: runs ARGS with --threads 1 and 2 (output
# to -o FILE, or stdout for .json) and compares the bytes.
same_with_threads() {
    local name=$1 ext=$2; shift 2
    for threads in 1 2; do
        local out=$work/$name.t$threads.$ext
        if [[ $ext == json ]]; then
            "$radiosity" "$@" --threads "$threads" --quiet --json >"$out" 2>"$work/err"
        else
            "$radiosity" "$@" --threads "$threads" --quiet -o "$out" 2>"$work/err"
        fi
        check "$name --threads $threads runs" test $? -eq 0
    done
    [[ $ext == json ]] && strip_time "$work/$name.t1.$ext" && strip_time "$work/$name.t2.$ext" &&
        ext=$ext.stripped
    check "$name: byte-identical with --threads 1 and 2" \
        cmp -s "$work/$name.t1.$ext" "$work/$name.t2.$ext"
    check "$name: output is not empty" test -s "$work/$name.t1.$ext"
}

small=(--elements 200)
for solver in direct jacobi gauss-seidel shooting; do
    same_with_threads "solve-$solver" json solve cornell "${small[@]}" --ff montecarlo \
        --ff-samples 16 --seed 7 --solver "$solver" --iterations 20
done
same_with_threads solve-raycast json solve cornell "${small[@]}" --ff raycast --seed 7
same_with_threads solve-hemicube json solve cornell "${small[@]}" --ff hemicube
same_with_threads render pfm render cornell "${small[@]}" --ff montecarlo --ff-samples 16 \
    --seed 7 --final-gather 4 --width 32 --height 24 --spp 2
same_with_threads render-png png render cornell "${small[@]}" --width 32 --height 24
same_with_threads pathtrace pfm pathtrace cornell-mirror --spp 4 --width 32 --height 24 --seed 7
same_with_threads bake glb bake cornell "${small[@]}" --ff montecarlo --ff-samples 16 --seed 7
same_with_threads formfactors json formfactors cornell "${small[@]}" --ff montecarlo \
    --ff-samples 16 --seed 7

# A different seed must give a different image (the seed reaches the random choices).
"$radiosity" pathtrace cornell-mirror --spp 4 --width 32 --height 24 --seed 8 --threads 2 \
    --quiet -o "$work/pathtrace.seed8.pfm"
check "pathtrace: another seed, another image" \
    bash -c "! cmp -s '$work/pathtrace.t1.pfm' '$work/pathtrace.seed8.pfm'"
"$radiosity" solve cornell "${small[@]}" --ff montecarlo --ff-samples 16 --seed 8 \
    --solver shooting --iterations 20 --threads 2 --quiet --json >"$work/solve.seed8.json"
strip_time "$work/solve.seed8.json"
check "solve: another seed, another solution" \
    bash -c "! cmp -s '$work/solve-shooting.t1.json.stripped' '$work/solve.seed8.json.stripped'"

finish
