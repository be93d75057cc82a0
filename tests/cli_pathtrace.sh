#!/usr/bin/env bash
# cli_pathtrace.sh - `radiosity pathtrace`: images in every format, the same image for the same
# seed whatever the thread count, and bad input: one line, exit 1 or 2, no file left behind.
# Usage: cli_pathtrace.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"

# Nothing but the files a test made on purpose: no temporaries, no half-written images.
no_stray_files() { test -z "$(ls "$work" | grep -v -e '^out$' -e '^err$' -e '^keep')"; }

small=(--width 24 --height 20 --spp 2 --quiet)

"$radiosity" pathtrace --help | grep -q -- '--max-bounces'; check "help" test $? -eq 0

# Every format; the PNG is a PNG, the PFM has its header and size.
for ext in png hdr pfm; do
    "$radiosity" pathtrace -o "$work/keep.$ext" "${small[@]}"
    check "writes .$ext" test -s "$work/keep.$ext"
done
check "png signature" test "$(head -c 4 "$work/keep.png" | tail -c 3)" = "PNG"
check "pfm header" test "$(head -c 11 "$work/keep.pfm" | tr '\n' ' ')" = "PF 24 20 -1"
check "hdr header" grep -q -a '#?RADIANCE' "$work/keep.hdr"
check "pfm size" test "$(stat -c %s "$work/keep.pfm")" -eq $((14 + 24 * 20 * 12))

# Same seed: the same bytes with 1 and 2 threads; another seed: other bytes.
"$radiosity" pathtrace cornell-mirror -o "$work/keep1.pfm" "${small[@]}" --seed 7 --threads 1
"$radiosity" pathtrace cornell-mirror -o "$work/keep2.pfm" "${small[@]}" --seed 7 --threads 2
"$radiosity" pathtrace cornell-mirror -o "$work/keep3.pfm" "${small[@]}" --seed 8 --threads 2
check "same seed, threads 1 and 2" cmp -s "$work/keep1.pfm" "$work/keep2.pfm"
differ() { ! cmp -s "$1" "$2"; }
check "another seed differs" differ "$work/keep1.pfm" "$work/keep3.pfm"

# --stats reports the rate.
"$radiosity" pathtrace -o "$work/keep.pfm" "${small[@]}" --stats >"$work/out"
check "stats" grep -q 'Mpaths/s' "$work/out"

# Usage errors: exit 2, nothing written.
expect_exit 2 'output file is required' -- "$radiosity" pathtrace "${small[@]}"
expect_exit 2 'unknown image format' -- "$radiosity" pathtrace -o "$work/x.jpg" "${small[@]}"
expect_exit 2 'unknown image format' -- "$radiosity" pathtrace -o "$work/x" "${small[@]}"
expect_exit 2 'unknown tone curve' -- "$radiosity" pathtrace -o "$work/x.png" --tonemap fancy "${small[@]}"
expect_exit 2 'each side must be 1 to' -- "$radiosity" pathtrace -o "$work/x.png" --spp 1 --width 0
expect_exit 2 'each side must be 1 to' -- "$radiosity" pathtrace -o "$work/x.png" --spp 1 --height 100000
expect_exit 2 'spp must be at least 1' -- "$radiosity" pathtrace -o "$work/x.png" --spp 0
expect_exit 2 'max-bounces must be at least 1' -- "$radiosity" pathtrace -o "$work/x.png" --max-bounces 0
expect_exit 2 'clamp must be 0 (off) or a positive' -- "$radiosity" pathtrace -o "$work/x.png" --clamp -1
expect_exit 2 'clamp wants a number' -- "$radiosity" pathtrace -o "$work/x.png" --clamp nan
expect_exit 2 'between 0 and 180' -- "$radiosity" pathtrace -o "$work/x.png" --fov 180
expect_exit 2 'wants X,Y,Z' -- "$radiosity" pathtrace -o "$work/x.png" --eye 1,2
expect_exit 2 'unexpected argument' -- "$radiosity" pathtrace cornell extra -o "$work/x.png"
check "usage errors leave no file" no_stray_files

# Errors: exit 1, nothing written.
expect_exit 1 'cannot write' -- "$radiosity" pathtrace -o "$work/no/such/dir/x.png" "${small[@]}"
expect_exit 1 'camera sees nothing' -- "$radiosity" pathtrace -o "$work/x.png" "${small[@]}" --look 278,273,-1600
expect_exit 1 'memory budget' -- "$radiosity" pathtrace -o "$work/x.pfm" --width 16384 --height 16384 --quiet
expect_exit 1 'no-such-scene' -- "$radiosity" pathtrace "$work/no-such-scene.obj" -o "$work/x.png" "${small[@]}"
expect_exit 1 'up must not be' -- "$radiosity" pathtrace -o "$work/x.png" "${small[@]}" --up 0,0,1
check "errors leave no file" no_stray_files

# One camera rule for every image command: the same warning, word for word, from render,
# pathtrace and photonmap for a camera inside the tall block (drawn: its backs are black,
# tests/cli_loose_ends.sh); and the automatic camera of a room without one
# (scenes/lights-room.gltf, which pathtrace and photonmap used to refuse as "inside an object")
# serves all three.
inside=(--eye 368,165,351 --look 368,165,600 --width 16 --height 16)
for command in render pathtrace photonmap; do
    "$radiosity" $command cornell "${inside[@]}" -o "$work/x.png" 2> "$work/$command.err"
    check "$command: the camera inside the tall block draws (a warning)" test $? -eq 0
    grep -v '^radiosity: \[' "$work/$command.err" > "$work/$command.msg"
done
rm -f "$work/x.png"
check "render and pathtrace: one message" cmp -s "$work/render.msg" "$work/pathtrace.msg"
check "pathtrace and photonmap: one message" cmp -s "$work/pathtrace.msg" "$work/photonmap.msg"
rm -f "$work"/*.err "$work"/*.msg
room="$source_dir/scenes/lights-room.gltf"
"$radiosity" pathtrace "$room" --width 16 --height 16 --spp 1 -o "$work/room_pt.pfm" --quiet
check "pathtrace lights-room without --eye: exit 0" test $? -eq 0
"$radiosity" photonmap "$room" --width 16 --height 16 --photons 1000 -o "$work/room_pm.pfm" --quiet 2>/dev/null
check "photonmap lights-room without --eye: exit 0" test $? -eq 0
rm -f "$work"/room_*.pfm


# A render that would take months (issue 16, tidy12): the first pass forecasts it, and the time
# budget stops it with the image so far and its real path count (before: no forecast, no budget,
# rows of 10^8 paths each that Ctrl-C could not stop).
"$radiosity" pathtrace cornell --spp 100000000 --width 32 --height 24 --time-budget 1 \
    -o "$work/keep.budget.pfm" 2>"$work/budget.err"
check "time budget: exit 0" test $? -eq 0
check "time budget: the image so far" test "$(stat -c %s "$work/keep.budget.pfm")" -eq $((14 + 32 * 24 * 12))
check "time budget: the forecast after the first pass" \
    grep -Eq '^radiosity: path tracing: 100000000 paths per pixel will take about [0-9.e+]+ (days|hours|minutes)' "$work/budget.err"
check "time budget: says how many paths" \
    grep -Eq '^radiosity: path tracing stopped \(time budget\) after [0-9.]+ s: [1-9][0-9]*( to [0-9]+)? of 100000000 paths per pixel' "$work/budget.err"
rm -f "$work/budget.err"
expect_exit 2 'time-budget must be a positive number' -- "$radiosity" pathtrace cornell --time-budget -1 -o "$work/x.png"

finish
