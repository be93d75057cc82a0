#!/usr/bin/env bash
# cli_render.sh - `radiosity render`: the default image, output formats by extension, the
# camera flags, --stats, and bad input (unknown extension, unwritable place, sizes, cameras that
# see nothing or only back faces): one line, exit 1 or 2, and no file left behind.
# Usage: cli_render.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"

# Nothing but the expected files in a directory.
only_files() { # only_files DIR FILE...
    local dir=$1; shift
    test "$(ls -A "$dir" | sort | tr '\n' ' ')" = "$(for f in "$@"; do echo "$f"; done | sort | tr '\n' ' ')"
}

small=(--width 48 --height 36 --spp 1 --elements 300 --quiet)

# The default: the built-in Cornell box to cornell.png in the working directory.
mkdir "$work/default"
(cd "$work/default" && "$radiosity" render --width 32 --height 32 --elements 200 --quiet)
check "render without arguments exits 0" test $? -eq 0
check "render without arguments writes cornell.png" only_files "$work/default" cornell.png
check "cornell.png is a PNG" test "$(head -c 8 "$work/default/cornell.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a

# Output by extension; PFM is linear: a 48 x 36 float image, header "PF 48 36 -1".
"$radiosity" render cornell "${small[@]}" -o "$work/c.pfm"
check "pfm written" test -s "$work/c.pfm"
check "pfm header" test "$(head -c 14 "$work/c.pfm" | tr '\n' ' ')" = "PF 48 36 -1.0 "
check "pfm size" test "$(stat -c %s "$work/c.pfm")" -eq $((14 + 48 * 36 * 12))
"$radiosity" render cornell "${small[@]}" -o "$work/c.hdr"
check "hdr written" grep -aq '#?RADIANCE' "$work/c.hdr"
"$radiosity" render cornell "${small[@]}" --shading flat --final-gather 2 --tonemap aces \
    --exposure 1 -o "$work/flat.png"
check "flat + final gather + aces" test -s "$work/flat.png"
"$radiosity" render cornell-mirror "${small[@]}" -o "$work/mirror.png"
check "cornell-mirror renders" test -s "$work/mirror.png"
# Camera flags override the scene's own camera.
"$radiosity" render unit-cube "${small[@]}" --eye 0.5,0.5,0.5 --look 0.5,0.5,2 --fov 120 \
    -o "$work/cube.pfm"
check "camera flags inside the unit cube" test -s "$work/cube.pfm"

# --stats: one line per step.
"$radiosity" render cornell "${small[@]}" --stats -o "$work/s.png" >"$work/stats"
check "stats: solve" grep -q '^solve ' "$work/stats"
check "stats: render with rays" grep -Eq '^render .*Mrays/s' "$work/stats"

# Usage errors: exit 2, no file.
mkdir "$work/bad"
expect_exit 2 'unknown image format' -- "$radiosity" render cornell -o "$work/bad/x.bmp"
expect_exit 2 'image size' -- "$radiosity" render cornell --width 0 -o "$work/bad/x.png"
expect_exit 2 'image size' -- "$radiosity" render cornell --height 100000 -o "$work/bad/x.png"
expect_exit 2 'spp' -- "$radiosity" render cornell --spp 0 -o "$work/bad/x.png"
expect_exit 2 'field of view' -- "$radiosity" render cornell --fov 200 -o "$work/bad/x.png"
expect_exit 2 'unknown shading' -- "$radiosity" render cornell --shading phong -o "$work/bad/x.png"
expect_exit 2 'tone curve' -- "$radiosity" render cornell --tonemap film -o "$work/bad/x.png"
expect_exit 2 'X,Y,Z' -- "$radiosity" render cornell --eye 1,2 -o "$work/bad/x.png"
expect_exit 2 'unexpected argument' -- "$radiosity" render cornell cornell -o "$work/bad/x.png"
for value in 2 yes "" -1; do
    expect_exit 2 'specular-first takes 1 or 0' -- "$radiosity" render cornell-mirror --specular-first "$value" -o "$work/bad/x.png"
done
for value in 0 -5 1e6 nan 2000000000 12x; do
    expect_exit 2 'specular-photons takes a whole number' -- "$radiosity" render cornell-mirror --specular-photons "$value" -o "$work/bad/x.png"
    expect_exit 2 'specular-photons takes a whole number' -- "$radiosity" bake cornell-mirror --specular-photons "$value" -o "$work/bad/x.glb"
done
expect_exit 2 'specular-first takes 1 or 0' -- "$radiosity" solve cornell-mirror --specular-first on

# Errors: exit 1, no file.
expect_exit 1 'x.png' -- "$radiosity" render cornell -o "$work/missing-dir/x.png"
mkdir "$work/locked" && chmod a-w "$work/locked"
if [ ! -w "$work/locked" ]; then # root can write anywhere
    expect_exit 1 'locked' -- "$radiosity" render cornell "${small[@]}" -o "$work/locked/x.png"
fi
expect_exit 1 'sees nothing' -- "$radiosity" render cornell "${small[@]}" --look 278,273,-1600 \
    -o "$work/bad/x.png"
expect_exit 1 'missing.obj' -- "$radiosity" render "$work/missing.obj" -o "$work/bad/x.png"
expect_exit 1 'patch system' -- "$radiosity" render four-walls -o "$work/bad/x.png"
check "no file left behind" only_files "$work/bad"

# A failed render never replaces an existing image.
cp "$work/c.pfm" "$work/keep.pfm"
"$radiosity" render cornell "${small[@]}" --look 278,273,-1600 -o "$work/keep.pfm" 2>/dev/null
check "existing image kept" cmp -s "$work/c.pfm" "$work/keep.pfm"

# A saved solution renders without solving: the same image as solving again; refused for
# another mesh, with no file left behind.
saved=(cornell --elements 300 --solver shooting --tolerance 1e-3 --width 32 --height 32 --quiet)
"$radiosity" solve cornell --elements 300 --solver shooting --tolerance 1e-3 --quiet \
    --save "$work/s.sol" >/dev/null
"$radiosity" render "${saved[@]}" -o "$work/solved.pfm"
"$radiosity" render "${saved[@]}" --solution "$work/s.sol" -o "$work/loaded.pfm"
check "rendering a saved solution equals solving" cmp -s "$work/solved.pfm" "$work/loaded.pfm"
mkdir -p "$work/other"
expect_exit 1 'different mesh' -- "$radiosity" render cornell --elements 400 --solution "$work/s.sol" \
    -o "$work/other/x.png" --width 32 --height 32 --quiet
check "no image for another mesh" only_files "$work/other"
expect_exit 2 'is the input' -- "$radiosity" render cornell --elements 300 --solution "$work/s.sol" \
    -o "$work/s.sol" --width 32 --height 32 --quiet

finish
