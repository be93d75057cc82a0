#!/usr/bin/env bash
# equal_error.sh - the solvers against path-traced references, for the issue's table of time to
# equal error (bench/README.md, "Time to equal error"): each row is one whole command, its
# processor time (user + system, /usr/bin/time) and wall time, and its image error in 8x8 and
# 16x16 blocks against the reference (scripts/block_compare.py --emitter inf). Rows without the
# final gather measure the solution itself; the path tracer's rows give its time-to-error curve.
# Timings only: nothing here passes or fails. Prints Markdown.
# Usage: bench/equal_error.sh RADIOSITY WORKDIR [cornell] [office] [sponza] [house] [officeN...]
#   References: /work/refs/cornell256_16k.pfm, /work/refs/sponza160_2048.pfm and an office
#   reference made here when missing (REFS=DIR to look elsewhere).
#   house and officeN (N triangles asked of the generator, e.g. office20000): shooting and the
#   hierarchy side by side below the default solver's threshold (bench/README.md, "Default
#   solver: ..."), against /work/refs/house128x96_1024.pfm and officeN_128x96_1024.pfm
#   (/work/refs/make_refs.sh hfin2). ROWS="pt shoot hier" (the default) picks the row groups, so
#   the slow shooting rows can run beside the others.
set -u
radiosity=$(realpath "$1")
work=$2
shift 2
scenes=${*:-cornell office sponza}
here=$(cd "$(dirname "$0")/.." && pwd)
refs=${REFS:-/work/refs}
mkdir -p "$work"
cd "$work" || exit 1

# row LABEL REF OUT -- COMMAND...: runs COMMAND (writing OUT), prints one table row.
row() {
    local label=$1 ref=$2 out=$3
    shift 4
    if ! /usr/bin/time -f "%U %S %e %M" -o time.txt "$@" >run.log 2>&1; then
        printf '| %s | failed: %s | | | | | |\n' "$label" "$(grep -v '^radiosity: \[' run.log | tail -1)"
        return
    fi
    read -r user sys wall kb <time.txt
    python3 "$here/scripts/block_compare.py" "$out" "$ref" --blocks 8,16 --emitter inf >cmp.txt
    local mean b8 b16 w16
    mean=$(sed -n 's/^mean .*(\(.*\))$/\1/p' cmp.txt)
    b8=$(sed -n 's/^8x8 blocks: relative RMSE \([^,]*\),.*/\1/p' cmp.txt)
    b16=$(sed -n 's/^16x16 blocks: relative RMSE \([^,]*\), worst \([^ ]*\).*/\1 (worst \2)/p' cmp.txt)
    printf '| %s | %.2f | %.1f | %d | %s | %s | %s |\n' "$label" "$(echo "$user + $sys" | bc)" \
        "$wall" $((kb / 1024)) "$mean" "$b8" "$b16"
}

# The input polygons of a scene file (scenes --info).
polygons() {
    "$radiosity" scenes --info "$1" 2>/dev/null | awk '$1 == "polygons" { print $2 }'
}

header() {
    echo
    echo "### $1"
    echo
    echo "| command | processor s | wall s | peak MB | mean | 8x8 RMSE | 16x16 RMSE |"
    echo "|---|---|---|---|---|---|---|"
}

# The rows of house and officeN: the path tracer's curve, shooting at two tolerances and the
# hierarchy at three link errors, all rendered with the final gather (the default render).
threshold_rows() {
    local ref=$1 scene=$2
    shift 2
    local view=("$@") groups=${ROWS:-pt shoot hier}
    if [[ $groups == *pt* ]]; then
        for spp in 16 64; do
            row "pathtrace --spp $spp" "$ref" pt.pfm -- "$radiosity" pathtrace "$scene" "${view[@]}" --spp $spp --seed 1 -o pt.pfm
        done
    fi
    if [[ $groups == *shoot* ]]; then
        row "render --solver shooting (final gather; to 1e-3 unshot)" "$ref" r.pfm -- "$radiosity" render "$scene" --solver shooting "${view[@]}" -o r.pfm
        row "render --solver shooting --tolerance 1e-2 (final gather)" "$ref" r.pfm -- "$radiosity" render "$scene" --solver shooting --tolerance 1e-2 "${view[@]}" -o r.pfm
    fi
    if [[ $groups == *hier* ]]; then
        for e in 1e-3 3e-4 1e-4; do
            row "render --solver hierarchical --link-error $e (final gather)" "$ref" r.pfm -- "$radiosity" render "$scene" --solver hierarchical --link-error $e "${view[@]}" -o r.pfm
        done
    fi
}

echo "load: $(uptime)"
for scene in $scenes; do
    case $scene in
    cornell)
        ref=$refs/cornell256_16k.pfm
        size=(--width 256 --height 256)
        header "Cornell box, 256 x 256, against $(basename "$ref")"
        for spp in 16 64 256; do
            row "pathtrace --spp $spp" "$ref" pt.pfm -- "$radiosity" pathtrace cornell "${size[@]}" --spp $spp --seed 1 -o pt.pfm
        done
        row "render (shooting, final gather)" "$ref" r.pfm -- "$radiosity" render cornell "${size[@]}" -o r.pfm
        for e in 1e-3 3e-4; do
            row "render --solver hierarchical --link-error $e (final gather)" "$ref" r.pfm -- "$radiosity" render cornell --solver hierarchical --link-error $e "${size[@]}" -o r.pfm
        done
        row "shooting, 10k elements, 1% unshot, no final gather" "$ref" r.pfm -- "$radiosity" render cornell --elements 10000 --tolerance 0.01 --final-gather 0 "${size[@]}" -o r.pfm
        row "gauss-seidel, 10k elements, 1e-3, no final gather" "$ref" r.pfm -- "$radiosity" render cornell --solver gauss-seidel --elements 10000 --tolerance 1e-3 --final-gather 0 "${size[@]}" -o r.pfm
        for e in 1e-3 1e-4 3e-5; do
            row "hierarchical --link-error $e, no final gather" "$ref" r.pfm -- "$radiosity" render cornell --solver hierarchical --link-error $e --final-gather 0 "${size[@]}" -o r.pfm
        done
        ;;
    office)
        "$radiosity" scenes --generate office 10000 office.obj --quiet 2>/dev/null ||
            "$radiosity" scenes --generate office 10000 office.obj >/dev/null 2>&1
        ref=${OFFICE_REF:-$refs/office10k128_512.pfm}
        size=(--width 128 --height 96)
        if [ ! -f "$ref" ]; then
            "$radiosity" pathtrace office.obj "${size[@]}" --spp 512 --seed 777 -o office_ref.pfm --quiet
            ref=$work/office_ref.pfm
        fi
        header "Generated office (scenes --generate office 10000: 4,652 faces), 128 x 96, against $(basename "$ref")"
        row "pathtrace --spp 16" "$ref" pt.pfm -- "$radiosity" pathtrace office.obj "${size[@]}" --spp 16 --seed 1 -o pt.pfm
        row "pathtrace --spp 64" "$ref" pt.pfm -- "$radiosity" pathtrace office.obj "${size[@]}" --spp 64 --seed 1 -o pt.pfm
        row "render (shooting, final gather: the default)" "$ref" r.pfm -- "$radiosity" render office.obj "${size[@]}" -o r.pfm
        row "shooting (2,500 elements asked), 1% unshot, no final gather" "$ref" r.pfm -- "$radiosity" render office.obj --tolerance 0.01 --final-gather 0 "${size[@]}" -o r.pfm
        row "gauss-seidel (2,500 elements asked), 1e-3, no final gather" "$ref" r.pfm -- "$radiosity" render office.obj --solver gauss-seidel --tolerance 1e-3 --final-gather 0 "${size[@]}" -o r.pfm
        row "hierarchical, no final gather" "$ref" r.pfm -- "$radiosity" render office.obj --solver hierarchical --final-gather 0 "${size[@]}" -o r.pfm
        row "hierarchical (final gather)" "$ref" r.pfm -- "$radiosity" render office.obj --solver hierarchical "${size[@]}" -o r.pfm
        ;;
    house)
        "$radiosity" scenes --generate house house.obj --quiet
        header "House (scenes --generate house: $(polygons house.obj) polygons), 128 x 96, against house128x96_1024.pfm"
        threshold_rows "$refs/house128x96_1024.pfm" house.obj --eye 0.3,1.7,0.3 --look 4.2,1.0,3.4 --fov 75 --width 128 --height 96
        ;;
    office[0-9]*)
        "$radiosity" scenes --generate office "${scene#office}" "$scene.obj" --quiet
        header "Generated office (scenes --generate office ${scene#office}: $(polygons "$scene.obj") polygons), 128 x 96, against ${scene}_128x96_1024.pfm"
        threshold_rows "$refs/${scene}_128x96_1024.pfm" "$scene.obj" --width 128 --height 96
        ;;
    sponza)
        obj=${SPONZA:-/work/shared/scenes/sponza/sponza_lit.obj}
        ref=$refs/sponza160_2048.pfm
        view=(--eye -10,3,0 --look 10,4,0 --fov 60 --width 160 --height 120)
        header "Sponza (sponza_lit.obj), 160 x 120, against $(basename "$ref")"
        row "shooting, 60 s budget, no final gather" "$ref" r.pfm -- "$radiosity" render "$obj" "${view[@]}" --time-budget 60 --final-gather 0 -o r.pfm
        row "gauss-seidel, no final gather" "$ref" r.pfm -- "$radiosity" render "$obj" "${view[@]}" --solver gauss-seidel --final-gather 0 -o r.pfm
        row "hierarchical, no final gather" "$ref" r.pfm -- "$radiosity" render "$obj" "${view[@]}" --solver hierarchical --final-gather 0 -o r.pfm
        row "render --solver hierarchical (final gather)" "$ref" r.pfm -- "$radiosity" render "$obj" "${view[@]}" --solver hierarchical -o r.pfm
        row "render (shooting, final gather), 60 s budget" "$ref" r.pfm -- "$radiosity" render "$obj" "${view[@]}" --time-budget 60 -o r.pfm
        row "pathtrace --spp 16" "$ref" pt.pfm -- "$radiosity" pathtrace "$obj" "${view[@]}" --spp 16 --seed 1 -o pt.pfm
        row "pathtrace --spp 64" "$ref" pt.pfm -- "$radiosity" pathtrace "$obj" "${view[@]}" --spp 64 --seed 1 -o pt.pfm
        ;;
    esac
done
echo
echo "load: $(uptime)"
