#!/usr/bin/env bash
# cli_lights.sh - lights that are not surfaces from the command line (docs/lights.md): --sun on a
# plane gives rho E cos in solve; --sky gives rho L on an open plane in render and pathtrace;
# scenes/lights-room.gltf (a point and a spot light from the file) renders within 2% of the
# path tracer in the mean; a point light's highlight on a rough mirror renders as the path
# tracer draws it; bake takes the flags; bad --sky/--sun values are usage errors (2) in
# every command; a bad or missing IES file or light name is one line (exit 1).
# Usage: cli_lights.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"
cd "$work" || exit 1

write_plane_obj

# ratio OUT: the mean ratio test / reference of `radiosity compare`.
ratio() { awk '/^mean/ { print $NF }' "$1"; }
# within VALUE EXPECTED TOLERANCE
within() { awk -v v="$1" -v e="$2" -v t="$3" 'BEGIN { exit !(v != "" && (v - e) <= t && (e - v) <= t) }'; }

# The sun at 45 degrees, E = 100: B = 0.5 * 100 * cos 45 on every element.
"$radiosity" solve plane.obj --sun 1,1,0,100 --elements 100 --quiet > sun.out 2> sun.err
check "solve --sun: exit 0" test $? -eq 0
check "solve --sun: B = rho E cos" within "$(awk '$1 == "floor" { print $3 }' sun.out)" 35.3553 0.001

# A uniform sky L = 2 over an open plane: radiance rho L = 1 everywhere in both images.
view="--eye 0,2,0.01 --look 0,0,0 --fov 40 --width 16 --height 16"
"$radiosity" render plane.obj --sky 2 $view --elements 100 -o sky_r.pfm --quiet
check "render --sky: exit 0" test $? -eq 0
"$radiosity" pathtrace plane.obj --sky 2 $view --spp 64 -o sky_pt.pfm --quiet
check "pathtrace --sky: exit 0" test $? -eq 0
printf 'PF\n16 16\n-1\n' > one.pfm
python3 -c "import struct,sys; sys.stdout.buffer.write(struct.pack('<768f', *([1.0] * 768)))" >> one.pfm
"$radiosity" compare sky_r.pfm one.pfm > c1.out
check "render --sky: rho L (mean $(ratio c1.out))" within "$(ratio c1.out)" 1 0.01
"$radiosity" compare sky_pt.pfm one.pfm > c2.out
check "pathtrace --sky: rho L (mean $(ratio c2.out))" within "$(ratio c2.out)" 1 0.01

# The room lit by its point and spot lights (glTF, candela): render against the path tracer.
room="$source_dir/scenes/lights-room.gltf"
view="--eye 0.3,2.6,0.3 --look 3,0,3 --fov 70 --width 48 --height 36"
"$radiosity" pathtrace "$room" $view --spp 256 -o room_pt.pfm --quiet
check "pathtrace lights-room: exit 0" test $? -eq 0
"$radiosity" render "$room" $view -o room_r.pfm --quiet
check "render lights-room: exit 0" test $? -eq 0
"$radiosity" compare room_r.pfm room_pt.pfm > c3.out
check "lights-room render / path tracer within 2% (mean $(ratio c3.out))" within "$(ratio c3.out)" 1 0.02
"$radiosity" bake "$room" --sun 0,1,0,1 --sky 0.1 --elements 500 -o room.ply --quiet
check "bake with --sun and --sky: exit 0" test $? -eq 0 -a -s room.ply

# A rough mirror under a point light, nothing else: every pixel is the lamp's glossy highlight,
# which render's second pass must sample as the path tracer does (it used to be black).
python3 - <<'PY'
import base64, json, struct
data = struct.pack('<12f', -2, 0, -2, -2, 0, 2, 2, 0, 2, 2, 0, -2) + struct.pack('<6H', 0, 1, 2, 0, 2, 3)
json.dump({
    "asset": {"version": "2.0"}, "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": [
        {"name": "bulb", "type": "point", "color": [1, 1, 1], "intensity": 100.0}]}},
    "scene": 0, "scenes": [{"nodes": [0, 1]}],
    "nodes": [{"name": "floor", "mesh": 0}, {"name": "bulb", "translation": [0, 1, 0.5],
              "extensions": {"KHR_lights_punctual": {"light": 0}}}],
    "materials": [{"name": "glossy", "pbrMetallicRoughness": {
        "baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 1.0, "roughnessFactor": 0.3}}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
    "buffers": [{"byteLength": len(data),
                 "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
    "bufferViews": [{"buffer": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                   "min": [-2, 0, -2], "max": [2, 0, 2]},
                  {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
}, open("glossy-floor.gltf", "w"))
PY
view="--eye 0,1,-2 --look 0,0,1.5 --fov 50 --width 32 --height 32"
"$radiosity" pathtrace glossy-floor.gltf $view --spp 64 -o gloss_pt.pfm --quiet
"$radiosity" render glossy-floor.gltf $view --elements 100 -o gloss_r.pfm --quiet
"$radiosity" compare gloss_r.pfm gloss_pt.pfm > c4.out
check "point light on a rough mirror: render / path tracer within 2% (mean $(ratio c4.out))" \
    within "$(ratio c4.out)" 1 0.02

# Usage errors in every command.
for command in solve render bake pathtrace; do
    out=""
    case $command in bake|pathtrace) out="-o x.pfm";; esac
    [ "$command" = bake ] && out="-o x.ply"
    for bad in "--sky -1" "--sky nan" "--sky cie-overcast:" "--sky 1,2" "--sky fog:1"; do
        expect_exit 2 "--sky takes" -- "$radiosity" $command plane.obj $bad $out
    done
    for bad in "--sun 0,1,0" "--sun 0,1,0,-2" "--sun 0,1,0,nan" "--sun 0,0,0,5" "--sun 0,1,0,1,2"; do
        expect_exit 2 "--sun takes" -- "$radiosity" $command plane.obj $bad $out
    done
    expect_exit 2 "requires a value\|needs a value\|missing" -- "$radiosity" $command plane.obj $out --sky
done

# IES files: missing, malformed (file:line), a light name the scene lacks, and a good one.
printf 'TILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 100\n0 90 45\n0\n1 1 1\n' > bad.ies
printf 'TILT=NONE\n1 1000 1 2 1 1 2 0 0 0\n1 1 100\n0 90\n0\n500 500\n' > good.ies
expect_exit 1 "missing.ies: No such file" -- "$radiosity" solve "$room" --ies missing.ies --quiet
expect_exit 1 "bad.ies:4: a vertical angle must increase" -- "$radiosity" solve "$room" --ies bulb=bad.ies --quiet
expect_exit 1 "no point or spot light named 'lamp'" -- "$radiosity" solve "$room" --ies lamp=good.ies --quiet
expect_exit 2 "--ies takes" -- "$radiosity" solve "$room" --ies =good.ies
"$radiosity" solve "$room" --ies bulb=good.ies --elements 400 --quiet > ies.out
check "solve --ies bulb=good.ies: exit 0" test $? -eq 0
"$radiosity" solve "$room" --elements 400 --quiet > plain.out
check "the IES profile changes the solution" test "$(awk '$1 == "floor" { print $3 }' ies.out)" != \
    "$(awk '$1 == "floor" { print $3 }' plain.out)"

# The hierarchical solver does not take lights yet: one line, exit 1.
expect_exit 1 "does not take point, spot or directional lights" -- "$radiosity" solve plane.obj --sun 0,1,0,1 --solver hierarchical --elements 100

finish
