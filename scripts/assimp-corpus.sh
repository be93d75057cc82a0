#!/usr/bin/env bash
# assimp-corpus.sh - runs every file under a directory (assimp's test/models and
# test/models-nonbsd, extracted by hand) through `radiosity solve` and counts how each ended:
# solved (exit 0), refused with one line (exit 1 or 2), killed by a signal (exit > 128 other
# than 130), hung (killed by timeout), or several lines of error output.
# Usage: scripts/assimp-corpus.sh MODELS_DIR [RADIOSITY] [SECONDS] [MAX_MEMORY_MIB]
#   (defaults: build/radiosity, 60 s per file, --max-memory 256)
# Getting the models: fetch github:assimp/assimp, then
#   git --git-dir=REPO archive HEAD test/models test/models-nonbsd | tar -x -C /tmp/assimp
# The exit status is 1 when any file was killed by a signal or hung. Each file's last line of
# stderr is written to assimp-corpus.log in the current directory.
set -uo pipefail
models=${1:?usage: scripts/assimp-corpus.sh MODELS_DIR [RADIOSITY] [SECONDS] [MAX_MEMORY_MIB]}
radiosity=${2:-build/radiosity}
seconds=${3:-60}
budget=${4:-256}
log=assimp-corpus.log
: >"$log"
solved=0 refused=0 signals=0 hangs=0 budget_overruns=0 multiline=0 total=0
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
while IFS= read -r -d '' file; do
    total=$((total + 1))
    status=0
    # A memory cap on the whole process tree (parent and import child) above the budget: what
    # passes it is an allocation the budget did not stop.
    (ulimit -v $(((budget + 1024) * 1024)); cd "$work" &&
        timeout -k 5 "$seconds" "$radiosity" solve "$file" --quiet --threads 1 \
            --elements 200 --iterations 50 --max-memory "$budget" >/dev/null 2>"$work/err") ||
        status=$?
    lines=$(grep -vc '^radiosity: warning:' "$work/err")
    last=$(tail -n 1 "$work/err")
    if ((status == 0)); then solved=$((solved + 1)); verdict=solved
    elif ((status == 124 || status == 137)); then hangs=$((hangs + 1)); verdict=HANG
    elif ((status > 128)); then signals=$((signals + 1)); verdict="SIGNAL $((status - 128))"
    else
        refused=$((refused + 1)); verdict="exit $status"
        if grep -q 'memory' "$work/err" && grep -q 'bad_alloc\|Cannot allocate' "$work/err"; then
            budget_overruns=$((budget_overruns + 1)); verdict="BUDGET $verdict"
        fi
        if ((lines > 1)); then multiline=$((multiline + 1)); verdict="MULTILINE $verdict"; fi
    fi
    printf '%s\t%s\t%s\n' "$verdict" "$file" "$last" >>"$log"
done < <(find "$models" -type f -print0 | sort -z)
echo "assimp-corpus: $total files: $solved solved, $refused refused ($multiline with more than" \
     "one line), $signals signals, $hangs hangs, $budget_overruns allocation failures past" \
     "the budget (details in $log)"
((signals == 0 && hangs == 0))
