#!/usr/bin/env bash
# output-checksums.sh - one line "NAME SHA256" per output of the built-in scenes, for checking
# that a refactoring changed no output bit (issue 11: "behaviour must not change"). Runs
# `solve --json` (the wall-clock "seconds" removed), `render` (PFM: smooth, flat, final gather,
# the hierarchical solver), `bake` (GLB), `pathtrace` (PFM) and a saved solution file, with one
# thread, small sizes (about a minute in all).
# Usage: scripts/output-checksums.sh RADIOSITY > before.txt; ...; diff before.txt after.txt
set -u
radiosity=${1:?usage: output-checksums.sh RADIOSITY}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
common=(--threads 1 --quiet)
small=(--elements 300)
image=(--width 48 --height 48)

sum() { printf '%s %s\n' "$1" "$(sha256sum <"$2" | cut -c1-16)"; }

for scene in cornell cornell-mirror four-walls unit-cube; do
    "$radiosity" solve "$scene" "${small[@]}" "${common[@]}" --json \
        | sed -E 's/"seconds": [0-9.eE+-]+/"seconds": _/g' >"$work/solve.json"
    sum "$scene/solve" "$work/solve.json"
    "$radiosity" solve "$scene" "${small[@]}" "${common[@]}" --save "$work/solution.rad" >/dev/null
    sum "$scene/solution" "$work/solution.rad"
    "$radiosity" render "$scene" "${small[@]}" "${image[@]}" --spp 2 "${common[@]}" \
        -o "$work/smooth.pfm" && sum "$scene/render-smooth" "$work/smooth.pfm"
    "$radiosity" render "$scene" "${small[@]}" "${image[@]}" --spp 2 --shading flat \
        "${common[@]}" -o "$work/flat.pfm" && sum "$scene/render-flat" "$work/flat.pfm"
    "$radiosity" render "$scene" "${small[@]}" "${image[@]}" --spp 1 --final-gather 8 \
        "${common[@]}" -o "$work/gather.pfm" && sum "$scene/render-gather" "$work/gather.pfm"
    "$radiosity" render "$scene" "${small[@]}" "${image[@]}" --spp 1 --solution \
        "$work/solution.rad" "${common[@]}" -o "$work/resumed.pfm" &&
        sum "$scene/render-from-file" "$work/resumed.pfm"
    "$radiosity" bake "$scene" "${small[@]}" "${common[@]}" -o "$work/bake.glb" &&
        sum "$scene/bake" "$work/bake.glb"
    "$radiosity" pathtrace "$scene" "${image[@]}" --spp 4 "${common[@]}" -o "$work/pt.pfm" &&
        sum "$scene/pathtrace" "$work/pt.pfm"
done
for ff in analytic raycast montecarlo hemicube; do
    "$radiosity" solve cornell "${small[@]}" --ff "$ff" "${common[@]}" --json \
        | sed -E 's/"seconds": [0-9.eE+-]+/"seconds": _/g' >"$work/solve.json"
    sum "cornell/solve-ff-$ff" "$work/solve.json"
done
for solver in direct jacobi gauss-seidel shooting importance hierarchical; do
    "$radiosity" solve cornell "${small[@]}" --solver "$solver" "${common[@]}" --json \
        | sed -E 's/"seconds": [0-9.eE+-]+/"seconds": _/g' >"$work/solve.json"
    sum "cornell/solve-$solver" "$work/solve.json"
done
"$radiosity" solve cornell "${small[@]}" --overshoot --ambient "${common[@]}" --json 2>/dev/null \
    | sed -E 's/"seconds": [0-9.eE+-]+/"seconds": _/g' >"$work/solve.json"
sum "cornell/solve-overshoot" "$work/solve.json"
"$radiosity" render cornell "${small[@]}" "${image[@]}" --spp 1 --solver hierarchical \
    "${common[@]}" -o "$work/hier.pfm" && sum "cornell/render-hierarchical" "$work/hier.pfm"
"$radiosity" bake cornell "${small[@]}" --solver hierarchical "${common[@]}" -o "$work/hier.glb" &&
    sum "cornell/bake-hierarchical" "$work/hier.glb"
