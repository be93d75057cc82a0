#!/usr/bin/env bash
# cli_scene_info.sh - `radiosity scenes --info SCENE [--json]` (cli/cmd_scenes.c,
# src/scene/scene_info.c): counts, bounds, materials with textures, surfaces, lights, camera and
# the import's warnings, in text and as one JSON object; bad input as everywhere.
# Usage: cli_scene_info.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"
cd "$work" || exit 1
python3 "$source_dir/scripts/make_textured_room.py" room.gltf

"$radiosity" scenes --info room.gltf >info.txt 2>info.err
check "text: exit 0" test $? -eq 0
check "text: polygon and triangle counts" grep -q "^polygons    7 (14 triangles), 28 vertices" info.txt
check "text: bounds" grep -q "^bounds      0 0 0  to  4 3 4" info.txt
check "text: the texture with its size" grep -q "checker .*texture checker.png (64 x 64)" info.txt
check "text: the textured surface" grep -q "^  floor .*textured$" info.txt
check "text: the lamp among the lights" grep -q "^lights      'lamp' (radiance 10 10 10)" info.txt
check "text: the file's camera" grep -q "^camera      the file's: eye 2 2.2 3.9" info.txt

# An OBJ with a lost texture and a bright material: the warnings go into the JSON too.
printf 'mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\no a\nusemtl white\nf 1/1 2/2 3/3 4/3\nusemtl nosuch\nf 4 3 1\n' >m.obj
printf 'newmtl white\nKd 1 1 1\nmap_Kd gone.png\n' >m.mtl
"$radiosity" scenes --info m.obj --json >info.json 2>json.err
check "json: exit 0" test $? -eq 0
check "json: the result" python3 - info.json <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d["geometric"] and d["polygons"] == 2 and d["triangles"] == 3, d
assert d["bounds"] == {"min": [0, 0, 0], "max": [1, 1, 0]}, d["bounds"]
assert d["camera"]["from_file"] is False
white = [m for m in d["materials"] if m["name"] == "white"][0]
assert white["texture"] is None and white["reflectance"] == [1, 1, 1], white
assert any("gone.png" in w for w in d["warnings"]), d["warnings"]
assert any("white because its texture" in w for w in d["warnings"]), d["warnings"]
assert any("usemtl 'nosuch'" in n for n in d["notes"]), d["notes"]
assert d["lights"] == [], d["lights"]
PY
"$radiosity" scenes --info four-walls --json >ffm.json 2>/dev/null
check "json: a patch system" python3 -c "import json; d = json.load(open('ffm.json')); assert not d['geometric'] and d['patches'] == 4, d"

# No camera in a closed room: the automatic camera stands inside, and render sees the room.
python3 -c "import json; d = json.load(open('room.gltf'))
d['nodes'] = [n for n in d['nodes'] if 'camera' not in n]; del d['cameras']
d['scenes'][0]['nodes'] = list(range(len(d['nodes']))); json.dump(d, open('nocam.gltf', 'w'))"
"$radiosity" scenes --info nocam.gltf --json >nocam.json 2>nocam.err
check "automatic camera: a note says so" grep -q "the automatic camera stands inside the largest open space" nocam.json
check "automatic camera: inside the room" python3 -c "import json; c = json.load(open('nocam.json'))['camera']
assert c['automatic'] == 'inside' and not c['from_file'], c
assert 0 < c['eye'][0] < 4 and 0 < c['eye'][1] < 3 and 0 < c['eye'][2] < 4, c"
"$radiosity" render nocam.gltf --elements 100 --width 16 --height 16 --spp 1 -o nocam.pfm 2>/dev/null
check "automatic camera: render sees the room" test -s nocam.pfm
"$radiosity" scenes --info "$source_dir/scenes/room.obj" --json >objroom.json 2>/dev/null
check "an open scene keeps the framing camera" python3 -c "import json
assert json.load(open('objroom.json'))['camera']['automatic'] == 'framing'"
# A closed house on a slab that runs out under its walls: from outside the framing camera sees
# fronts (the slab, the walls), but the lamp's light stays inside, so the camera goes in.
"$radiosity" scenes --generate house house.obj >/dev/null 2>&1
"$radiosity" scenes --info house.obj --json >house.json 2>/dev/null
check "a lamp inside a closed house: the camera inside" python3 -c "import json
assert json.load(open('house.json'))['camera']['automatic'] == 'inside'"
expect_exit 0 "place it with --eye and --look" -- "$radiosity" render nocam.gltf --quiet \
    --elements 100 --width 16 --height 16 --eye 2,1.5,-1 --look 2,1.5,2 -o "$work/outside.pfm"

# A 3DS camera (z-up file, turned y-up by assimp) comes in upright: up +y, not -z (rolled).
python3 - <<'PY'
import struct
def chunk(cid, body): return struct.pack("<HI", cid, 6 + len(body)) + body
verts = [(-2, -2, 0), (2, -2, 0), (2, 4, 0), (-2, 4, 0), (-2, 4, 0), (2, 4, 0), (2, 4, 3), (-2, 4, 3)]
faces = [(0, 1, 2), (0, 2, 3), (4, 7, 6), (4, 6, 5)]   # floor (+z) and back wall (-y)
vb = struct.pack("<H", len(verts)) + b"".join(struct.pack("<3f", *v) for v in verts)
fb = struct.pack("<H", len(faces)) + b"".join(struct.pack("<4H", *f, 0) for f in faces)
mesh = chunk(0x4000, b"room\0" + chunk(0x4100, chunk(0x4110, vb) + chunk(0x4120, fb)))
# camera: position, target, roll, lens
camera = chunk(0x4000, b"Camera01\0" + chunk(0x4700, struct.pack("<8f", 0, -1.5, 1.5, 0, 4, 1.2, 0, 35)))
editor = chunk(0x3D3D, chunk(0x3D3E, struct.pack("<I", 3)) + mesh + camera)
open("room.3ds", "wb").write(chunk(0x4D4D, chunk(0x0002, struct.pack("<I", 3)) + editor))
PY
"$radiosity" scenes --info room.3ds --json >3ds.json 2>/dev/null
check "3DS camera: upright (up +y), eye and view as the file says" python3 -c "import json
c = json.load(open('3ds.json'))['camera']
assert c['from_file'] and abs(c['up'][1] - 1) < 1e-9 and abs(c['up'][2]) < 1e-9, c
assert [round(x, 6) for x in c['eye']] == [0, 1.5, 1.5], c
d = [c['look'][k] - c['eye'][k] for k in range(3)]
assert d[2] < -0.99 and d[1] < 0, c"

# glTF doubleSided: a panel between two lamps, one above and one below, gets a back surface;
# both faces receive light (a one-sided panel's back would stay black).
python3 - <<'PY'
import base64, json, struct
positions = [(-0.5, 0, -0.5), (-0.5, 0, 0.5), (0.5, 0, 0.5), (0.5, 0, -0.5)]   # faces +y
binary = b"".join(struct.pack("<3f", *p) for p in positions) + struct.pack("<6H", 0, 1, 2, 0, 2, 3)
def material(name, double, emit):
    m = {"name": name, "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0}}
    if double: m["doubleSided"] = True
    if emit: m["emissiveFactor"] = [1, 1, 1]
    return m
json.dump({"asset": {"version": "2.0"},
    "buffers": [{"byteLength": len(binary), "uri": "data:application/octet-stream;base64," + base64.b64encode(binary).decode()}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-0.5, 0, -0.5], "max": [0.5, 0, 0.5]},
                  {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
    "materials": [material("panel", True, False), material("lamp", False, True)],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": m}]} for m in (0, 1)],
    "nodes": [{"name": "panel", "mesh": 0},
              {"name": "above", "mesh": 1, "translation": [0, 1, 0], "rotation": [1, 0, 0, 0]},
              {"name": "below", "mesh": 1, "translation": [0, -1, 0]}],
    "scenes": [{"nodes": [0, 1, 2]}], "scene": 0}, open("panel.gltf", "w"))
PY
"$radiosity" solve panel.gltf --elements 50 --json >panel.json 2>panel.err
check "doubleSided: both faces of the panel receive light" python3 -c "import json
p = {s['name']: s['radiosity'][0] for s in json.load(open('panel.json'))['patches']}
assert p['panel'] > 0.05 and abs(p['panel (back)'] - p['panel']) < 0.02 * p['panel'], p"

# Lights that are not surfaces: the file's point and spot lights with their units, the flags'
# sun, sky and IES profile (scenes --info takes the light flags of solve and render).
room="$source_dir/scenes/lights-room.gltf"
printf 'TILT=NONE\n1 1000 1 2 1 1 2 0 0 0\n1 1 100\n0 90\n0\n500 500\n' > good.ies
"$radiosity" scenes --info "$room" --sun 0,1,0,100 --sky 0.5 --ies bulb=good.ies >lights.txt 2>/dev/null
check "text lights: exit 0" test $? -eq 0
check "text lights: the point light, W/sr and cd, its IES file" grep -q \
    "^  point 'bulb' at 1.2 2.5 1: intensity 1 0.9 0.8 W/sr (179 161.1 143.2 cd), IES profile good.ies" lights.txt
check "text lights: the spot with its cone" grep -q "^  spot 'spot' at 2.8 2.9 2.6, axis .*cone 20.* to 29.* degrees: intensity 2.4 2.7 3 W/sr (429.6 483.3 537 cd)" lights.txt
check "text lights: the sun" grep -q "^  directional 'sun' travelling -0 -1 -0: irradiance 100 100 100 W/m^2 (17900 17900 17900 lux)" lights.txt
check "text lights: the sky" grep -q "^  sky uniform, radiance 0.5 0.5 0.5 W/(m^2 sr), zenith 0 1 0" lights.txt
check "text lights: not 'nothing emits'" test "$(grep -c 'nothing emits' lights.txt)" -eq 0
"$radiosity" scenes --info "$room" --json --sun 0,1,0,100 >lights.json 2>/dev/null
check "json lights: kinds, positions, units" python3 - lights.json <<'PY'
import json, sys
lights = json.load(open(sys.argv[1]))["lights"]
kinds = [l["kind"] for l in lights]
assert kinds == ["point", "spot", "directional"], kinds
bulb, spot, sun = lights
assert bulb["name"] == "bulb" and abs(bulb["position"][1] - 2.5) < 1e-6 and bulb["ies"] is None, bulb
assert abs(bulb["intensity_cd"][0] - 179) < 1e-3 and abs(bulb["intensity_w_sr"][0] - 1) < 1e-6, bulb
assert abs(spot["outer_degrees"] - 29.79) < 0.01 and spot["inner_degrees"] < spot["outer_degrees"], spot
assert sun["direction"] == [-0.0, -1.0, -0.0] and sun["irradiance_w_m2"] == [100, 100, 100], sun
PY

expect_exit 1 "nothere.obj" -- "$radiosity" scenes --info nothere.obj
expect_exit 2 "json goes with --info" -- "$radiosity" scenes --json
expect_exit 2 "unexpected argument" -- "$radiosity" scenes --info room.gltf extra
finish
