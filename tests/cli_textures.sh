#!/usr/bin/env bash
# cli_textures.sh - textures (src/scene/texture.c, docs/rendering.md "Textures"): the textured
# glTF room of scripts/make_textured_room.py, with its checker as a file and embedded.
#   - the solve bleeds the floor's colour: the walls come out redder than with the texture gone;
#   - the pattern shows in render (final gather and smooth reconstruction) and in the path
#     tracer: a red square and a cream square of the floor, at the same pixels in each;
#   - the embedded image gives the same solution as the file;
#   - a texture that is missing, not an image, truncated or over the memory budget: a warning
#     naming it and the colour factor, exit 0, and the factor used (walls not red).
# Python starts slowly here, so it runs twice: to make the scenes, and to read every result.
# Usage: cli_textures.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"
cd "$work" || exit 1
python3 "$source_dir/scripts/make_textured_room.py" room.gltf
python3 "$source_dir/scripts/make_textured_room.py" embedded.gltf --embed --texture unused.png
rm -f unused.png
solve() { "$radiosity" solve "$1" --elements 300 --tolerance 1e-4 --json "${@:2}"; }

solve room.gltf >textured.json 2>textured.err
check "no texture warning for the good texture" bash -c "! grep -q texture textured.err"
solve embedded.gltf >embedded.json 2>/dev/null

# Bad textures: the room with its image named bad.png, which is ...
for what in missing text truncated huge; do
    sed 's/"checker.png"/"bad.png"/' room.gltf >bad.gltf
    extra=()
    case $what in
        missing) rm -f bad.png ;;
        text) echo "this is not an image" >bad.png ;;
        truncated) head -c 80 checker.png >bad.png ;;
        huge) # a PNG header claiming 30000 x 30000 texels (2.5 GiB decoded), then nothing
            printf '\x89PNG\r\n\x1a\n\x00\x00\x00\x0dIHDR\x00\x00\x75\x30\x00\x00\x75\x30\x08\x02\x00\x00\x00\x00\x00\x00\x00' >bad.png
            extra=(--max-memory 256) ;;
    esac
    solve bad.gltf "${extra[@]}" >"bad-$what.json" 2>bad.err
    status=$?
    check "$what texture: exit 0 (got $status)" test "$status" -eq 0
    check "$what texture: a warning naming it" grep -q "texture '[^']*bad.png' not used" bad.err
    check "$what texture: the warning gives the colour factor" grep -q "colour factor 0.9 0.9 0.9" bad.err
done

# Materials: a reflectance of 0.95 or more (named with its surfaces), white because its texture
# is missing, and a usemtl naming a material the MTL lacks (a note with the line).
cat >bright.obj <<'OBJ'
mtllib bright.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
o lamp
usemtl light
f 1 2 3 4
o wall
usemtl plaster
f 4 3 2 1
o tiles
usemtl nosuch
f 1 3 4
OBJ
printf 'newmtl light\nKd 0.5 0.5 0.5\nKe 1 1 1\nnewmtl plaster\nKd 0.96 0.9 0.9\n' >bright.mtl
printf 'newmtl textured\nKd 1 1 1\nmap_Kd gone.png\n' >>bright.mtl
sed -i 's/^usemtl plaster$/usemtl plaster/; $a o floor\nusemtl textured\nvt 0 0\nvt 1 0\nvt 1 1\nf 1/1 2/2 3/3' bright.obj
"$radiosity" solve bright.obj --elements 50 >/dev/null 2>bright.err
check "reflectance 0.96: a warning naming the material and its surface" \
    grep -q "material 'plaster' reflects 0.96 of the light (surfaces 'wall')" bright.err
check "white because the texture is missing: said so" \
    grep -q "material 'textured' reflects 1 of the light, white because its texture could not be used (surfaces 'floor')" bright.err
check "usemtl of a material the MTL lacks: a note with its line" \
    grep -q "bright.obj:13: usemtl 'nosuch' names a material the MTL files lack" bright.err
check "no warning for the lamp's 0.5" bash -c "! grep -q \"'light' reflects\" bright.err"

"$radiosity" render room.gltf --elements 300 --width 48 --height 48 -o fg.pfm 2>/dev/null
"$radiosity" render room.gltf --elements 300 --width 48 --height 48 --final-gather 0 -o smooth.pfm 2>/dev/null
"$radiosity" pathtrace room.gltf --width 48 --height 48 --spp 64 -o pt.pfm 2>/dev/null

# Every number, in one run of Python: "PASS name" or "FAIL name" lines.
python3 - >results <<'PY'
import json
from pfm import read_pfm
def wall(name):  # red / green of the left wall's radiosity
    try:
        w = [p for p in json.load(open(name))["patches"] if p["name"] == "left"][0]["radiosity"]
        return w[0] / w[1]
    except Exception:
        return float("nan")
def pixel(name, x, y):  # red / green at pixel (x, y) of a PFM (rows bottom to top)
    try:
        w, h, d = read_pfm(name)
        r, g = d[3 * ((h - 1 - y) * w + x)], d[3 * ((h - 1 - y) * w + x) + 1]
        return r / max(g, 1e-9)
    except Exception:
        return float("nan")
def report(ok, name):
    print(("PASS " if ok else "FAIL ") + name)
t = wall("textured.json")
report(t > 1.15, "walls bleed the floor's red: R/G %.3f > 1.15" % t)
e = wall("embedded.json")
report(abs(t - e) < 1e-9, "embedded image: the same walls (R/G %.6f and %.6f)" % (t, e))
for what in ("missing", "text", "truncated", "huge"):
    b = wall("bad-%s.json" % what)
    report(b < 1.05, "%s texture: the factor is used, walls grey (R/G %.3f < 1.05)" % (what, b))
# The floor square under pixel (27, 40) is red, the one under (20, 40) cream.
for image in ("fg", "smooth", "pt"):
    red, cream = pixel(image + ".pfm", 27, 40), pixel(image + ".pfm", 20, 40)
    report(red > 4 and cream < 1.6,
           "%s: a red square (R/G %.2f > 4) beside a cream one (R/G %.2f < 1.6)" % (image, red, cream))
PY
while read -r verdict name; do
    check "$name" test "$verdict" = PASS
    echo "$verdict $name"
done <results
check "every result was read" test "$(wc -l <results)" -eq 9
finish
