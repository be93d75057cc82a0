#!/usr/bin/env bash
# cli_scenes.sh - `radiosity scenes` and `scenes --export`, and the sample scene files through
# `solve`: built-in scenes written as OBJ/MTL and read back give the same surfaces, areas and
# radiosities; glTF, GLB, OBJ and PLY samples come in with their names.
# Usage: cli_scenes.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"

# Surfaces of a solve --json: one line "name area r g b" each.
surfaces() {
    sed -n 's/.*"name": "\([^"]*\)", "area": \([^,]*\), "radiosity": \[\([^,]*\), \([^,]*\), \([^]]*\)\].*/\1 \2 \3 \4 \5/p' "$1"
}
# same_surfaces A B AREA-TOLERANCE RADIOSITY-TOLERANCE: same names in the same order, areas and
# radiosities within the relative tolerances.
same_surfaces() {
    surfaces "$1" >"$work/a.txt"
    surfaces "$2" >"$work/b.txt"
    test -s "$work/a.txt" || return 1
    paste -d ' ' "$work/a.txt" "$work/b.txt" | awk -v ta="$3" -v tr="$4" '
        function rel(x, y) { d = x - y; if (d < 0) d = -d; m = (x < 0 ? -x : x); if ((y < 0 ? -y : y) > m) m = (y < 0 ? -y : y); return m > 0 ? d / m : 0 }
        { if ($1 != $6 || rel($2, $7) > ta) bad = 1
          for (c = 3; c <= 5; ++c) { r = rel($c, $(c + 5)); if (r > worst) worst = r; if (r > tr) bad = 1 } }
        END { printf "  largest relative radiosity difference %.2g\n", worst > "/dev/stderr"; exit bad }'
}
solve_json() { # solve_json SCENE OUT
    "$radiosity" solve "$1" --elements 300 --ff analytic --tolerance 1e-9 --json --quiet >"$2" 2>"$work/solve-err"
}

# The list.
"$radiosity" scenes >"$work/list"
for name in four-walls cornell cornell-mirror two-squares unit-cube; do
    check "scenes lists $name" grep -q "^$name " "$work/list"
done

# Export the Cornell box: one object per surface, materials with Kd and Ke.
"$radiosity" scenes --export cornell "$work/cornell.obj"
check "export cornell exits 0" test $? -eq 0
check "cornell.obj written" test -s "$work/cornell.obj"
check "cornell.mtl written" test -s "$work/cornell.mtl"
check "mtllib names the MTL" grep -qx 'mtllib cornell.mtl' "$work/cornell.obj"
for surface in floor ceiling back-wall green-wall red-wall light short-block tall-block; do
    check "object $surface" grep -qx "o $surface" "$work/cornell.obj"
done
check "eight objects" test "$(grep -c '^o ' "$work/cornell.obj")" -eq 8
check "light emits radiance 17 12 4" grep -qx 'Ke 17 12 4' "$work/cornell.mtl"
check "red reflectance" grep -qx 'Kd 0.63 0.065 0.05' "$work/cornell.mtl"
check "no temporary files left" test "$(ls "$work" | grep -c tmp)" -eq 0

# Read back: same names, areas and radiosities within 1e-6 (assimp reads coordinates as float,
# 1e-8 apart from the built-in ones; test_import also compares with the float-rounded scene).
solve_json cornell "$work/builtin.json"
solve_json "$work/cornell.obj" "$work/export.json"
check "cornell round trip" same_surfaces "$work/builtin.json" "$work/export.json" 1e-6 1e-6
for name in two-squares unit-cube; do
    "$radiosity" scenes --export $name "$work/$name.obj"
    check "export $name" test $? -eq 0
    solve_json $name "$work/$name-builtin.json"
    solve_json "$work/$name.obj" "$work/$name-export.json"
    check "$name round trip" same_surfaces "$work/$name-builtin.json" "$work/$name-export.json" 1e-6 1e-6
done
"$radiosity" scenes --export cornell-mirror "$work/mirror.obj"
check "export cornell-mirror" test $? -eq 0
check "cornell-mirror has a mirror" grep -qx 'illum 3' "$work/mirror.mtl"

# Any scene file can be exported too: glTF mirror and glass hints survive as illum 3 and 7.
"$radiosity" scenes --export "$source_dir/scenes/lamp-room.glb" "$work/lamp-room.obj" --quiet
check "export a GLB" test $? -eq 0
check "metal as illum 3" grep -qx 'illum 3' "$work/lamp-room.mtl"
check "glass as illum 7" grep -qx 'illum 7' "$work/lamp-room.mtl"

# Sample scenes: names as the files give them (made unique), GLB equal to glTF.
solve_json "$source_dir/scenes/lamp-room.gltf" "$work/gltf.json"
solve_json "$source_dir/scenes/lamp-room.glb" "$work/glb.json"
check "glTF surfaces" test "$(surfaces "$work/gltf.json" | cut -d' ' -f1 | tr '\n' ' ')" = \
    "floor lamp shelf shelf.2 pane mirror "
check "GLB equals glTF" same_surfaces "$work/gltf.json" "$work/glb.json" 0 0
solve_json "$work/lamp-room.obj" "$work/lamp-room-obj.json"
check "glTF -> OBJ keeps names and areas" same_surfaces "$work/gltf.json" "$work/lamp-room-obj.json" 1e-6 1e-2
"$radiosity" solve "$source_dir/scenes/room.obj" --elements 200 --json >"$work/room.json" 2>"$work/room-err"
check "room.obj solves" test $? -eq 0
check "room.obj surfaces" test "$(surfaces "$work/room.json" | cut -d' ' -f1 | tr '\n' ' ')" = \
    "floor lamp wall/red wall/white mirror glass block step "
check "room.obj drops two faces" grep -q 'warning: .*room.obj: dropped 2 degenerate faces' "$work/room-err"
"$radiosity" solve "$source_dir/scenes/square.ply" --elements 50 --json >"$work/ply.json" 2>"$work/ply-err"
check "PLY solves" test $? -eq 0
surfaces "$work/ply.json" >"$work/ply-surfaces"
check "PLY surface named after the file, area 1.5" awk '$1 == "square" && ($2 - 1.5) ^ 2 < 1e-20 { found = 1 } END { exit !found }' "$work/ply-surfaces"
check "PLY has no emitter" grep -q 'warning: .*nothing emits light' "$work/ply-err"

# Errors.
expect_exit 1 'patch system' -- "$radiosity" scenes --export four-walls "$work/four-walls.obj"
check "nothing written for four-walls" test ! -e "$work/four-walls.obj"
expect_exit 1 'no-such-scene' -- "$radiosity" scenes --export no-such-scene "$work/x.obj"
expect_exit 1 'cornell\|x.obj' -- "$radiosity" scenes --export cornell "$work/no/such/dir/x.obj"
check "nothing left behind" test ! -e "$work/no"
expect_exit 2 'needs a scene and an output file' -- "$radiosity" scenes --export cornell
expect_exit 2 'needs a value' -- "$radiosity" scenes --export
expect_exit 2 'unexpected argument' -- "$radiosity" scenes cornell
expect_exit 2 'unexpected argument' -- "$radiosity" scenes --export cornell a.obj b.obj

finish
