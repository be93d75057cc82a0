#!/usr/bin/env bash
# cli_photonmap.sh - `radiosity photonmap` (docs/photonmapping.md): an image, the same image for
# the same seed whatever the thread count, --progressive, and bad input: one line, exit 1 or 2,
# no file left behind.
# Usage: cli_photonmap.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"

no_stray_files() { test -z "$(ls "$work" | grep -v -e '^out$' -e '^err$' -e '^keep')"; }

small=(--width 24 --height 20 --spp 1 --gather 4 --photons 5000 --quiet)

"$radiosity" photonmap --help | grep -q -- '--caustic-photons'; check "help" test $? -eq 0
"$radiosity" --help | grep -q 'photonmap'; check "listed" test $? -eq 0

"$radiosity" photonmap cornell-mirror -o "$work/keep.pfm" "${small[@]}"
check "writes .pfm" test "$(head -c 11 "$work/keep.pfm" | tr '\n' ' ')" = "PF 24 20 -1"

# Same seed: the same bytes with 1 and 2 threads; another seed: other bytes.
"$radiosity" photonmap cornell-mirror -o "$work/keep1.pfm" "${small[@]}" --seed 7 --threads 1
"$radiosity" photonmap cornell-mirror -o "$work/keep2.pfm" "${small[@]}" --seed 7 --threads 2
"$radiosity" photonmap cornell-mirror -o "$work/keep3.pfm" "${small[@]}" --seed 8 --threads 2
check "same seed, threads 1 and 2" cmp -s "$work/keep1.pfm" "$work/keep2.pfm"
differ() { ! cmp -s "$1" "$2"; }
check "another seed differs" differ "$work/keep1.pfm" "$work/keep3.pfm"
"$radiosity" photonmap cornell -o "$work/keep4.pfm" "${small[@]}" --progressive 3 --threads 1
"$radiosity" photonmap cornell -o "$work/keep5.pfm" "${small[@]}" --progressive 3 --threads 2
check "progressive, threads 1 and 2" cmp -s "$work/keep4.pfm" "$work/keep5.pfm"

"$radiosity" photonmap -o "$work/keep.pfm" "${small[@]}" --stats >"$work/out"
check "stats" grep -q 'Mphotons/s' "$work/out"

# Usage errors: exit 2, nothing written.
expect_exit 2 'output file is required' -- "$radiosity" photonmap "${small[@]}"
expect_exit 2 'photons must be at least 1' -- "$radiosity" photonmap -o "$work/x.png" --photons 0
expect_exit 2 'wants a whole number' -- "$radiosity" photonmap -o "$work/x.png" --photons -5
expect_exit 2 'wants a whole number' -- "$radiosity" photonmap -o "$work/x.png" --photons nan
expect_exit 2 'caustic-photons must be at least 1' -- "$radiosity" photonmap -o "$work/x.png" --caustic-photons 0
expect_exit 2 'radius must be positive' -- "$radiosity" photonmap -o "$work/x.png" --radius 0
expect_exit 2 'radius must be positive' -- "$radiosity" photonmap -o "$work/x.png" --radius -1
expect_exit 2 'wants a number' -- "$radiosity" photonmap -o "$work/x.png" --radius nan
expect_exit 2 'gather must be at least 1' -- "$radiosity" photonmap -o "$work/x.png" --gather 0
expect_exit 2 'nearest must be at least 2' -- "$radiosity" photonmap -o "$work/x.png" --nearest 1
expect_exit 2 'spp must be at least 1' -- "$radiosity" photonmap -o "$work/x.png" --spp 0
expect_exit 2 'unknown image format' -- "$radiosity" photonmap -o "$work/x.jpg" "${small[@]}"
check "usage errors leave no file" no_stray_files

# Errors: exit 1, nothing written; the budget is checked before any photon is stored.
expect_exit 1 'memory budget' -- "$radiosity" photonmap -o "$work/x.pfm" --photons 1000000000000 --quiet
expect_exit 1 'memory budget' -- "$radiosity" photonmap -o "$work/x.pfm" --photons 20000000 --max-memory 64 --quiet
expect_exit 1 'camera sees nothing' -- "$radiosity" photonmap -o "$work/x.png" "${small[@]}" --look 278,273,-1600
expect_exit 1 'cannot write' -- "$radiosity" photonmap -o "$work/no/such/dir/x.png" "${small[@]}"
check "errors leave no file" no_stray_files

# Textures: photons and the camera read the texture at the hit, as the path tracer does (a
# texture's white factor alone made the textured room twice as bright: measured +104%, now -0.4%
# at 48 x 48 against 256 spp).
python3 "$source_dir/scripts/make_textured_room.py" "$work/keep_room.gltf" > /dev/null
"$radiosity" pathtrace "$work/keep_room.gltf" --width 32 --height 32 --spp 64 -o "$work/keep_room_pt.pfm" --quiet
"$radiosity" photonmap "$work/keep_room.gltf" --width 32 --height 32 --spp 2 --photons 50000 -o "$work/keep_room_pm.pfm" --quiet
mean=$(python3 "$source_dir/scripts/block_compare.py" "$work/keep_room_pm.pfm" "$work/keep_room_pt.pfm" --blocks 16 --worst 0 |
       sed -n 's/^mean .*(\([-+0-9.]*\)%)$/\1/p')
check "textured room: photon map mean within 3% of the path tracer's ($mean%)" \
    python3 -c "import sys; sys.exit(0 if abs(float('$mean')) < 3 else 1)"

# Photons from every light (scene/light_emission.h): the point and spot lights of lights-room.gltf,
# and a sky and a sun over an open corner, against the path tracer's mean (measured at 32 x 24:
# see docs/photonmapping.md, "Lights").
light_mean() { # SCENE ARGS...: the photon map's mean against the path tracer's, in percent
    local scene=$1; shift
    "$radiosity" pathtrace "$scene" --width 32 --height 24 --spp 64 "$@" -o "$work/keep_lpt.pfm" --quiet
    "$radiosity" photonmap "$scene" --width 32 --height 24 --spp 2 --photons 50000 "$@" -o "$work/keep_lpm.pfm" --quiet
    python3 "$source_dir/scripts/block_compare.py" "$work/keep_lpm.pfm" "$work/keep_lpt.pfm" --blocks 8 --worst 0 \
        --emitter inf | sed -n 's/^mean .*(\([-+0-9.]*\)%)$/\1/p'
}
mean=$(light_mean "$source_dir/scenes/lights-room.gltf")
check "point and spot lights: photon map mean within 3% of the path tracer's ($mean%)" \
    python3 -c "import sys; sys.exit(0 if abs(float('$mean')) < 3 else 1)"
printf 'v 0 0 0\nv 4 0 0\nv 4 0 4\nv 0 0 4\nv 0 3 0\nv 0 3 4\nv 4 3 4\nf 1 4 3 2\nf 1 5 6 4\nf 4 6 7 3\n' > "$work/keep_corner.obj"
mean=$(light_mean "$work/keep_corner.obj" --sky 1 --sun 0.5,1,0.3,3 --eye 6,4,-3 --look 1,0.5,2)
check "sky and sun: photon map mean within 3% of the path tracer's ($mean%)" \
    python3 -c "import sys; sys.exit(0 if abs(float('$mean')) < 3 else 1)"
expect_exit 2 'sun takes' -- "$radiosity" photonmap -o "$work/x.png" --sun 1,2
expect_exit 2 'sky takes' -- "$radiosity" photonmap -o "$work/x.png" --sky -1

# render's caustic map (docs/specular-first.md): its photons past a quarter of the budget are a
# warning, and the render goes on with the deposit.
"$radiosity" render cornell-mirror --width 16 --height 16 --spp 1 --elements 200 --specular-photons 100000 \
    --max-memory 1 -o "$work/keep_caustic.png" \
    2> "$work/err" > /dev/null
check "caustic map over the budget: exit 0" test $? -eq 0
check "caustic map over the budget: a warning" grep -q 'not kept for the caustic map' "$work/err"

finish
