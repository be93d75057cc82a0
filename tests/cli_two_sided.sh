#!/usr/bin/env bash
# cli_two_sided.sh - `--two-sided` (rad_scene_set_two_sided, src/scene/two_sided.c): both faces
# of every surface receive and reflect, in solve, render, bake, pathtrace, photonmap and
# scenes --info; emitters stay one-sided; a glTF doubleSided material is not doubled twice; a
# patch system is refused in one line.
# Usage: cli_two_sided.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"
cd "$work" || exit 1

# A grey plane facing +y, lit by a sun from below (travelling up).
write_plane_obj
sun="--sun 0,-1,0,100"

# radiosity SURFACE FILE: the surface's red radiosity in `solve` output.
radiosity_of() { awk -v s="$1" '{ name = $1; for (i = 2; i <= NF - 7; ++i) name = name " " $i }
    name == s { print $(NF - 5) }' "$2"; }
within() { awk -v v="$1" -v e="$2" -v t="$3" 'BEGIN { exit !(v != "" && (v - e) <= t && (e - v) <= t) }'; }

"$radiosity" solve plane.obj $sun --elements 50 --quiet > one.out
check "one-sided: the plane's back gets nothing" test "$(grep -c 'floor (back)' one.out)" -eq 0
check "one-sided: floor B = 0" within "$(radiosity_of floor one.out)" 0 1e-9
"$radiosity" solve plane.obj $sun --elements 50 --quiet --two-sided > two.out
check "solve --two-sided: exit 0" test $? -eq 0
check "solve --two-sided: the back B = rho E = 50" within "$(radiosity_of 'floor (back)' two.out)" 50 1e-6

# Seen from below: one-sided, the camera sees only backs (drawn black, a warning:
# tests/cli_loose_ends.sh); two-sided, render and the path tracer agree.
view="--eye 0,-2,0.01 --look 0,0,0 --fov 40 --width 16 --height 16"
expect_exit 0 "sees only the backs" -- "$radiosity" render plane.obj $sun $view --elements 50 -o r.pfm --quiet
"$radiosity" render plane.obj --two-sided $sun $view --elements 50 -o r.pfm --quiet
check "render --two-sided: exit 0" test $? -eq 0
"$radiosity" pathtrace plane.obj --two-sided $sun $view --spp 16 -o pt.pfm --quiet
check "pathtrace --two-sided: exit 0" test $? -eq 0
"$radiosity" compare r.pfm pt.pfm > c.out
check "render / path tracer from below within 1% ($(awk '/^mean/ { print $NF }' c.out))" \
    within "$(awk '/^mean/ { print $NF }' c.out)" 1 0.01

# bake writes both faces (the element budget shared by them); photonmap takes the flag; emitters stay one-sided (the Cornell light).
"$radiosity" bake plane.obj --two-sided $sun --elements 50 -o two.ply --quiet
check "bake --two-sided: the back is baked" grep -aq "^comment surface .*: floor (back)$" two.ply
"$radiosity" photonmap cornell --two-sided --width 8 --height 8 --photons 2000 -o pm.pfm --quiet
check "photonmap --two-sided: exit 0" test $? -eq 0 -a -s pm.pfm
"$radiosity" scenes --info cornell --two-sided > cornell.txt 2>/dev/null
check "scenes --info --two-sided: backs listed" grep -q "^  floor (back) " cornell.txt
check "scenes --info --two-sided: the light stays one-sided" test "$(grep -c '^  light (back)' cornell.txt)" -eq 0

# A glTF doubleSided panel is not given a second back.
python3 - <<'PY'
import base64, json, struct
binary = struct.pack("<12f", -0.5, 0, -0.5, -0.5, 0, 0.5, 0.5, 0, 0.5, 0.5, 0, -0.5) + struct.pack("<6H", 0, 1, 2, 0, 2, 3)
json.dump({"asset": {"version": "2.0"},
    "buffers": [{"byteLength": len(binary), "uri": "data:application/octet-stream;base64," + base64.b64encode(binary).decode()}],
    "bufferViews": [{"buffer": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-0.5, 0, -0.5], "max": [0.5, 0, 0.5]},
                  {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
    "materials": [{"name": "panel", "doubleSided": True, "pbrMetallicRoughness": {"metallicFactor": 0}}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
    "nodes": [{"name": "panel", "mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}, open("panel.gltf", "w"))
PY
"$radiosity" scenes --info panel.gltf --two-sided --json > panel.json 2>/dev/null
check "doubleSided and --two-sided: one back" python3 -c "import json
names = [s['name'] for s in json.load(open('panel.json'))['surfaces']]
assert names == ['panel', 'panel (back)'], names"

expect_exit 1 "two-sided surfaces need geometry" -- "$radiosity" solve "$source_dir/scenes/four-walls.ffm" --two-sided
finish
