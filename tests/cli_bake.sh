#!/usr/bin/env bash
# cli_bake.sh - `radiosity bake`: each format is written and looks like itself; bad names and
# unwritable places give one line, exit 1 or 2, and leave no file and no temporary behind.
# Usage: cli_bake.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"

# nothing_in DIR: the directory is empty (no output, no temporary).
nothing_in() { test -z "$(ls -A "$1")"; }

"$radiosity" bake --help | grep -q -- '--tonemap' ; check "bake --help" test $? -eq 0

# Each format, small and fast.
out="$work/out-files"
mkdir "$out"
small=(--elements 60 --tolerance 1e-3 --quiet)
"$radiosity" bake unit-cube -o "$out/cube.glb" "${small[@]}"; check "glb exit" test $? -eq 0
check "glb magic" test "$(head -c 4 "$out/cube.glb")" = glTF
check "glb unlit" grep -aq '"KHR_materials_unlit"' "$out/cube.glb"
"$radiosity" bake cornell -o "$out/box.gltf" "${small[@]}" --scale 0.001; check "gltf exit" test $? -eq 0
check "gltf bin" test -s "$out/box.bin"
check "gltf uri" grep -q '"uri": "box.bin"' "$out/box.gltf"
check "gltf camera" grep -q '"type": "perspective"' "$out/box.gltf"
check "gltf names" grep -q '"name": "red-wall"' "$out/box.gltf"
"$radiosity" bake unit-cube -o "$out/cube.PLY" "${small[@]}" --exposure 1 --tonemap aces
check "ply exit" test $? -eq 0
check "ply header" grep -aq 'format binary_little_endian 1.0' "$out/cube.PLY"
check "ply radiance" grep -aq 'property float radiance_r' "$out/cube.PLY"
check "ply comment" grep -aq 'exposure 1 stops and tone curve aces' "$out/cube.PLY"
"$radiosity" bake unit-cube -o "$out/cube.obj" "${small[@]}"; check "obj exit" test $? -eq 0
check "obj colours" grep -Eq '^v [-0-9.e]+ [-0-9.e]+ [-0-9.e]+ [0-9.e]+ [0-9.e]+ [0-9.e]+$' "$out/cube.obj"
check "obj groups" test "$(grep -c '^g ' "$out/cube.obj")" -eq 6
check "obj objects" test "$(grep -c '^o ' "$out/cube.obj")" -eq 6
check "only the outputs" test "$(ls "$out" | sort | tr '\n' ' ')" = "box.bin box.gltf cube.PLY cube.glb cube.obj "
# The summary line.
"$radiosity" bake unit-cube -o "$out/cube.glb" --elements 60 >"$work/stdout"
check "summary" grep -Eq '^baked [0-9]+ elements of 6 surfaces into .*cube.glb' "$work/stdout"

# Usage errors (exit 2), checked before any work: nothing is written.
empty="$work/empty"
mkdir "$empty"
expect_exit 2 'unknown bake format' -- "$radiosity" bake unit-cube -o "$empty/cube.png"
expect_exit 2 'unknown bake format' -- "$radiosity" bake unit-cube -o "$empty/cube"
expect_exit 2 'unknown tone curve' -- "$radiosity" bake unit-cube -o "$empty/cube.ply" --tonemap filmic
expect_exit 2 'where to' -- "$radiosity" bake unit-cube
expect_exit 2 'which scene' -- "$radiosity" bake -o "$empty/cube.glb"
expect_exit 2 'unknown solver' -- "$radiosity" bake unit-cube -o "$empty/cube.glb" --solver magic
expect_exit 2 'positive' -- "$radiosity" bake unit-cube -o "$empty/cube.glb" --scale -1
check "usage errors leave nothing" nothing_in "$empty"
# Writing over the scene it reads: refused, the scene untouched.
"$radiosity" bake unit-cube -o "$work/scene.obj" "${small[@]}"
cp "$work/scene.obj" "$work/scene-before.obj"
expect_exit 2 'is the input' -- "$radiosity" bake "$work/scene.obj" -o "$work/scene.obj"
check "input untouched" cmp -s "$work/scene.obj" "$work/scene-before.obj"

# Unwritable places (exit 1): a missing directory, a file where a directory should be.
expect_exit 1 'cannot write' -- "$radiosity" bake unit-cube -o "$empty/missing/cube.glb"
touch "$empty/plain"
expect_exit 1 'cannot write' -- "$radiosity" bake unit-cube -o "$empty/plain/cube.gltf"
check "unwritable leaves nothing" test "$(ls -A "$empty")" = plain
# A .gltf that cannot be renamed into place (a directory is in the way): no .bin, no temporary.
mkdir -p "$empty/busy.gltf/inside"
expect_exit 1 'busy.gltf' -- "$radiosity" bake unit-cube -o "$empty/busy.gltf" --elements 24
check "failed gltf leaves no bin" test "$(ls -A "$empty" | sort | tr '\n' ' ')" = "busy.gltf plain "

# A patch system has no geometry.
expect_exit 1 'no geometry' -- "$radiosity" bake four-walls -o "$empty/walls.glb"
check "patch system leaves nothing" test ! -e "$empty/walls.glb"

finish
