#!/usr/bin/env bash
# photon_vs_pathtrace.sh - error against processor time for the path tracer and photon mapping
# on cornell-mirror (issue 14: photon mapping should reach the path tracer's 1024-spp error in at
# most 1/5 of its time). Every run in one go, under the same load; error = 8x8-block relative
# RMSE (scripts/block_compare.py) against a far-converged reference of the same size.
# Usage: bench/photon_vs_pathtrace.sh RADIOSITY REFERENCE.pfm [SIZE] [SCENE]
#   (SIZE 128: the reference's; SCENE cornell-mirror, or cornell with /work/refs/cornell128_16k.pfm)
# Prints a Markdown table: command, processor seconds (user + system), mean, 4x4, 8x8 and 16x16
# block RMSE.
set -euo pipefail
radiosity=$1
reference=$2
size=${3:-128}
scene=${4:-cornell-mirror}
here=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMP_WAIT_POLICY=passive
echo "| command | processor s | mean | 4x4 RMSE | 8x8 RMSE | 16x16 RMSE |"
echo "|---|---|---|---|---|---|"
run() {
    local out=$work/x.pfm
    /usr/bin/time -f "%U %S" -o "$work/time" "$radiosity" "$@" --width "$size" --height "$size" \
        --seed 1 -o "$out" --quiet
    local cpu
    cpu=$(awk '{printf "%.2f", $1 + $2}' "$work/time")
    local errors
    errors=$(python3 "$here/scripts/block_compare.py" "$out" "$reference" --blocks 4,8,16 --worst 0)
    local mean rmse4 rmse8 rmse16
    mean=$(sed -n 's/^mean .*(\(.*\))$/\1/p' <<<"$errors")
    rmse4=$(sed -n 's/^4x4 blocks: relative RMSE \([0-9.]*%\).*/\1/p' <<<"$errors")
    rmse8=$(sed -n 's/^8x8 blocks: relative RMSE \([0-9.]*%\).*/\1/p' <<<"$errors")
    rmse16=$(sed -n 's/^16x16 blocks: relative RMSE \([0-9.]*%\).*/\1/p' <<<"$errors")
    echo "| \`$*\` | $cpu | $mean | $rmse4 | $rmse8 | $rmse16 |"
}
for spp in 64 256 1024; do run pathtrace "$scene" --spp "$spp"; done
run photonmap "$scene" --spp 8 --gather 8
run photonmap "$scene" --spp 16 --gather 8
run photonmap "$scene" --spp 16 --gather 8 --photons 400000
run photonmap "$scene" --spp 24 --gather 4 --photons 400000
run photonmap "$scene" --spp 32 --gather 4 --photons 400000
run photonmap "$scene" --spp 32 --gather 8 --photons 400000
