#!/usr/bin/env bash
# cli_units.sh - the solution does not depend on the length unit (docs/units.md): scenes/room.obj
# scaled by 1e15 and by 1e-15 solves to the radiosities of the unscaled room (every patch and
# channel within 1e-5 relative; measured 1.2e-7) and renders the same picture (relative MSE
# below 1e-8; measured 1e-15). Before coordinates were normalised for Embree (scene/rays.h,
# rad_ray_frame) the scaled rooms lost the lamp's shadow (floor 12% too bright) and the render
# of the 1e15 room saw nothing.
# Usage: cli_units.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"
cd "$work" || exit 1
cp "$source_dir/scenes/room.mtl" .
for scale in 1 1e15 1e-15; do
    awk -v s="$scale" '$1 == "v" { printf "v %.17g %.17g %.17g\n", $2 * s, $3 * s, $4 * s; next }
                       { print }' "$source_dir/scenes/room.obj" >"room_$scale.obj"
    "$radiosity" solve "room_$scale.obj" --quiet --json --threads 1 >"solve_$scale.json" 2>/dev/null
    check "solve of the room scaled by $scale" test -s "solve_$scale.json"
    # The renderer's own rays (camera, one gather ray, light samples) on the element mesh.
    "$radiosity" render "room_$scale.obj" --quiet --width 24 --height 24 -o "room_$scale.pfm" \
        --final-gather 1 --specular-first 0 --threads 1 --no-gather-filter 2>/dev/null
    check "render of the room scaled by $scale" test -s "room_$scale.pfm"
    # With the irradiance filter (src/render/gather_filter.c): its lengths are ratios only, but
    # which neighbours fall inside a pixel's window is a discrete choice that the scaled rooms'
    # differences (relative MSE 2e-9 without it) can flip: measured 1.0e-6 at 1e-15.
    "$radiosity" render "room_$scale.obj" --quiet --width 24 --height 24 -o "filtered_$scale.pfm" \
        --final-gather 1 --specular-first 0 --threads 1 2>/dev/null
done

same_radiosity() {
    python3 - "$1" "$2" <<'PY'
import json, sys
a, b = (json.load(open(f))["patches"] for f in sys.argv[1:3])
assert len(a) == len(b) and a, "patch lists differ"
worst = max(abs(x - y) / max(abs(x), 1e-9)
            for p, q in zip(a, b) for x, y in zip(p["radiosity"], q["radiosity"]))
lit = sum(p["radiosity"][0] > 0 for p in a)
print(f"{sys.argv[2]}: worst relative radiosity difference {worst:.3g} over {lit} lit patches")
sys.exit(0 if worst < 1e-5 and lit >= 3 else 1)
PY
}
same_picture() { # A B LIMIT: relative MSE of A against B below LIMIT
    "$radiosity" compare "$1" "$2" --json >compare.json &&
        python3 -c 'import json, sys; sys.exit(0 if json.load(open("compare.json"))["relative_mse"] < float(sys.argv[1]) else 1)' "$3"
}
for scale in 1e15 1e-15; do
    check "radiosity of the room scaled by $scale" same_radiosity solve_1.json "solve_$scale.json"
    check "picture of the room scaled by $scale" same_picture "room_$scale.pfm" room_1.pfm 1e-8
    check "filtered picture of the room scaled by $scale" same_picture "filtered_$scale.pfm" filtered_1.pfm 1e-5
done
finish
