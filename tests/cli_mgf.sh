#!/usr/bin/env bash
# cli_mgf.sh - MGF input (src/scene/mgf.c): scenes/cornell.mgf against the same box written
# in OBJ here (same surfaces and areas; renders within 1% in the mean, relative MSE < 1e-4), the
# tessellated primitives (areas against their closed forms, and facing outwards: an emitting
# primitive inside a closed box lights the box), includes and transforms, and bad input (one
# line FILE:LINE, exit 1).
# Usage: cli_mgf.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"
cd "$work" || exit 1

# The OBJ twin: the colours converted by hand from the chromaticities (sRGB primaries, white
# E: a colour at a primary's chromaticity is that channel alone, scaled by the luminance weight
# of the primary), the emission ed / (pi 179) = 10.
python3 - <<'PY'
import math
xy = [(0.64, 0.33), (0.30, 0.60), (0.15, 0.06)]
# Columns X/Y, 1, Z/Y of the primaries; weights w solve M w = (1, 1, 1) (white E).
m = [[x / y for x, y in xy], [1.0, 1.0, 1.0], [(1 - x - y) / y for x, y in xy]]
def det(a):
    return (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]))
d = det(m)
w = []
for k in range(3):
    a = [row[:] for row in m]
    for i in range(3): a[i][k] = 1.0
    w.append(det(a) / d)
red, green = 0.25 / w[0], 0.25 / w[1]
light = 5623.4508 / (math.pi * 179)
open("twin.mtl", "w").write(f"""newmtl white
Kd 0.75 0.75 0.75
newmtl red
Kd {red:.9f} 0 0
newmtl green
Kd 0 {green:.9f} 0
newmtl light
Kd 0.5 0.5 0.5
Ke {light:.9f} {light:.9f} {light:.9f}
""")
open("twin.obj", "w").write("""mtllib twin.mtl
v 0 0 0
v 0 0 1
v 1 0 1
v 1 0 0
v 0 1 0
v 0 1 1
v 1 1 1
v 1 1 0
v 0.4 0.99 0.4
v 0.6 0.99 0.4
v 0.6 0.99 0.6
v 0.4 0.99 0.6
v 0.2 0 0.2
v 0.2 0 0.45
v 0.45 0 0.45
v 0.45 0 0.2
v 0.2 0.3 0.2
v 0.2 0.3 0.45
v 0.45 0.3 0.45
v 0.45 0.3 0.2
o floor
usemtl white
f 1 2 3 4
o ceiling
usemtl white
f 5 8 7 6
o back-wall
usemtl white
f 1 4 8 5
o red-wall
usemtl red
f 1 5 6 2
o green-wall
usemtl green
f 4 3 7 8
o light
usemtl light
f 9 10 11 12
o block
usemtl white
f 13 16 15 14
f 17 18 19 20
f 13 14 18 17
f 14 15 19 18
f 15 16 20 19
f 16 13 17 20
""")
PY

surfaces() { # surfaces FILE: "name area" per surface, from solve --json
    "$radiosity" solve "$1" --elements 400 --json --quiet |
        python3 -c 'import json, sys; [print(p["name"], "%.9f" % p["area"]) for p in json.load(sys.stdin)["patches"]]'
}
surfaces "$source_dir/scenes/cornell.mgf" >mgf.surfaces
surfaces twin.obj >obj.surfaces
check "MGF reads: 7 surfaces" test "$(wc -l <mgf.surfaces)" -eq 7
# (assimp reads OBJ in single precision: areas agree to 1e-6.)
check "same surfaces and areas as the OBJ twin" python3 -c '
import sys
a = [l.split() for l in open("mgf.surfaces")]
b = [l.split() for l in open("obj.surfaces")]
sys.exit(0 if len(a) == len(b) and all(x[0] == y[0] and abs(float(x[1]) / float(y[1]) - 1) < 1e-6
                                       for x, y in zip(a, b)) else 1)'

view=(--eye 0.5,0.5,2.4 --look 0.5,0.5,0 --fov 40 --width 48 --height 48 --spp 4 --elements 600
      --quiet)
"$radiosity" render "$source_dir/scenes/cornell.mgf" -o mgf.pfm "${view[@]}"
check "render the MGF box" test $? -eq 0
"$radiosity" render twin.obj -o obj.pfm "${view[@]}"
"$radiosity" compare mgf.pfm obj.pfm --json >cmp.json
check "MGF and OBJ renders agree in the mean within 1%" python3 -c '
import json, sys; d = json.load(open("cmp.json")); sys.exit(0 if abs(d["mean_ratio"] - 1) < 0.01 else 1)'
check "MGF and OBJ renders agree pixel by pixel" python3 -c '
import json, sys; d = json.load(open("cmp.json")); sys.exit(0 if d["relative_mse"] < 1e-4 else 1)'
check "the box is lit" python3 -c '
import json, sys; d = json.load(open("cmp.json")); sys.exit(0 if d["mean_reference"] > 0.01 else 1)' \
    || cat cmp.json >&2

# Primitives: areas against closed forms (24 segments: within 3%), and outward: an emitting
# primitive inside a closed white box (faces inward) lights the box.
box='v a =
	p -3 -3 -3
v b =
	p 3 -3 -3
v c =
	p 3 3 -3
v d =
	p -3 3 -3
v e =
	p -3 -3 3
v f =
	p 3 -3 3
v g =
	p 3 3 3
v h =
	p -3 3 3
m wall =
	rd 0.5
o box
m wall
f a b c d
f e h g f
f a e f b
f b f g c
f c g h d
f d h e a
o
m lamp =
	ed 1000
v o =
	p 0 0 0
	n 0 0 1
v top =
	p 0 0 1.5
v t1 =
	p 0.5 0 0
v t2 =
	p 0 0.5 0
v t3 =
	p -0.5 -0.5 0
o shape
m lamp
'
primitive() { # primitive NAME MGF-LINE AREA: area within 3%, the box receives light
    printf '%s%s\no\n' "$box" "$2" >"$1.mgf"
    "$radiosity" solve "$1.mgf" --elements 300 --tolerance 1e-3 --json --quiet >"$1.json" 2>"$1.err"
    check "$1: solves" test $? -eq 0 || cat "$1.err" >&2
    check "$1: area within 3% of $3" python3 -c "
import json, sys
d = {p['name']: p for p in json.load(open('$1.json'))['patches']}
sys.exit(0 if abs(d['shape']['area'] / ($3) - 1) < 0.03 else 1)"
    check "$1: faces outward (the box is lit)" python3 -c "
import json, sys
d = {p['name']: p for p in json.load(open('$1.json'))['patches']}
sys.exit(0 if d['box']['radiosity'][1] > 1e-3 else 1)"
}
pi=3.141592653589793
primitive sph 'sph o 1' "4*$pi"
primitive cyl 'cyl o 0.5 top' "2*$pi*0.5*1.5"
primitive cone 'cone o 1 top 0' "$pi*1*(1+1.5**2)**0.5"
primitive ring 'ring o 0.5 1' "$pi*(1-0.25)"
primitive torus 'torus o 0.5 1.5' "4*$pi**2*1*0.5"
primitive prism 'prism t1 t2 t3 1' "2*0.375+1*(0.5**2+0.5**2)**0.5+2*1*(0.5**2+1)**0.5"
# Inward primitives (negative radius) light nothing outside them.
printf '%s%s\no\n' "$box" 'sph o -1' >inward.mgf
"$radiosity" solve inward.mgf --elements 300 --tolerance 1e-3 --json --quiet >inward.json 2>/dev/null
check "sph with a negative radius faces inward" python3 -c "
import json, sys
d = {p['name']: p for p in json.load(open('inward.json'))['patches']}
sys.exit(0 if d['box']['radiosity'][1] < 1e-9 else 1)"

# Includes with a transform, and xf: the light square of a file included twice, moved.
mkdir -p parts
cat >parts/square.mgf <<'MGF'
v s0 =
	p 0 0 0
v s1 =
	p 1 0 0
v s2 =
	p 1 1 0
v s3 =
	p 0 1 0
f s0 s1 s2 s3
MGF
cat >two.mgf <<'MGF'
m grey =
	rd 0.5
o pair
m grey
i parts/square.mgf
i parts/square.mgf -s 2 -t 5 0 0
xf -rz 90 -t 0 0 3
i parts/square.mgf
xf
o
MGF
surfaces two.mgf >two.surfaces 2>/dev/null # (nothing emits: a warning)
check "includes: one surface of area 1 + 4 + 1" grep -q '^pair 6.0000' two.surfaces

# Names: an object with a second material is "object/material"; a material redefined (here in
# an array of 3 copies, each a new grey) numbers on; a redefined vertex is the newest one
# (polygons apart: no coplanar overlaps).
cat >names.mgf <<'MGF'
v a =
	p 0 0 0
v b =
	p 1 0 0
v c =
	p 0 1 0
m lamp =
	ed 100
o box
m lamp
f a b c
xf -t 0 0 1 -a 3 -t 0 0 1
m grey =
	rd 0.5
f a b c
xf
o
v c =
	p 0 2 0
m grey
xf -t 0 0 -1
f a b c
xf
MGF
surfaces names.mgf >names.surfaces
check "MGF names: box, box/grey, box/grey.3, box/grey.4, grey" \
    test "$(cut -d' ' -f1 names.surfaces | tr '\n' ' ')" = "box box/grey box/grey.3 box/grey.4 grey "
check "MGF names: the redefined vertex c makes a triangle of area 1" grep -q '^grey 1.0000' names.surfaces

# Bad input: one line FILE:LINE, exit 1.
bad() { # bad FILE TEXT PATTERN: solve refuses FILE (holding TEXT) with one line PATTERN, exit 1
    printf "$2" >"$1"
    expect_exit 1 "$3" -- "$radiosity" solve "$1"
}
bad undef.mgf 'v a =\n\tp 0 0 0\nf a b c\n' 'undef.mgf:3: undefined vertex: b'
bad bright.mgf 'm x =\n\trd 1.5\n' 'bright.mgf:2: reflectance must be in'
bad nan.mgf 'v a =\n\tp 0 zero 0\n' 'nan.mgf:2: not a number: zero'
bad inc.mgf 'i missing.mgf\n' 'inc.mgf:1: cannot include'
bad inc2.mgf 'i inc2.mgf\n' 'includes nested too deep'
bad open.mgf 'o open\n' 'not ended'
bad empty.mgf '# nothing\n' 'empty.mgf: no faces'
bad array0.mgf 'xf -a 0 -t 1 0 0\nxf\n' 'array0.mgf:1: xf -a: the count must be a whole number from 1 to 100000: 0'
bad array1.mgf 'xf -a 2.5 -t 1 0 0\nxf\n' 'array1.mgf:1: xf -a: the count must be a whole number'
bad array2.mgf 'xf -a 1000 -t 1 0 0\nxf -a 1000 -t 0 1 0\nxf\nxf\n' 'array2.mgf:3: xf -a: more than 100000 copies in all'
bad array3.mgf 'xf -a 3 -t 1 0 0\n' 'array3.mgf: a transform (xf) not ended'
bad cxy.mgf 'c x =\n\tcxy 0.7 0.5\n' 'cxy.mgf:2: chromaticity outside'
# A short file of arrays asks for millions of polygons: the memory budget stops it.
printf 'm x =\n\trd 0.5\nv c =\n\tp 0 0 0\nxf -a 100000 -t 3 0 0\nsph c 1\nxf\n' >spheres.mgf
expect_exit 1 "the MGF scene's geometry needs .* over the memory budget of 64.0 MiB" -- \
    "$radiosity" scenes --info spheres.mgf --max-memory 64
bad device.mgf 'i /dev/null\n' 'device.mgf:1: cannot include /dev/null: not a regular file'
# A reflectance of 0.95 or more is read, with the warning every reader gives.
printf 'm white =\n\tc\n\trd 0.97\nv a =\n\tp 0 0 0\nv b =\n\tp 1 0 0\nv c =\n\tp 1 1 0\no floor\nf a b c\no\n' \
    >white.mgf
"$radiosity" scenes --info white.mgf >/dev/null 2>white.err
check "a 0.97 reflectance is warned about, naming the surface" \
    grep -q "white.mgf: material 'white' reflects 0.97 of the light (surfaces 'floor')" white.err \
    || cat white.err >&2
# rd + rs over 1 (RenderPark's own cube.mgf has rd 0.9 with rs 0.2): read, both scaled to a
# total of 1, with a warning at the line.
printf 'm shiny =\n\trd 0.9\n\trs 0.2 0.01\nv a =\n\tp 0 0 0\nv b =\n\tp 1 0 0\nv c =\n\tp 1 1 0\no floor\nf a b c\no\n' \
    >shiny.mgf
"$radiosity" scenes --info shiny.mgf >/dev/null 2>shiny.err
check "rd + rs over 1 is read (exit 0)" test $? -eq 0
check "rd + rs over 1 is warned about once, naming the material where it is first used" \
    test "$(grep -c "shiny.mgf:11: material 'shiny' has rd + rs = 1.1, more than 1" shiny.err)" = 1 \
    || cat shiny.err >&2
# The scaled values: rd 0.9 / 1.1 (grey, so R = G = B). Scaled where the material is used, not
# where rd or rs is read: a material made from it that sets rs 0 keeps rd 0.9, as in RenderPark.
printf 'm shiny =\n\trd 0.9\n\trs 0.2 0.01\nm matte = shiny\n\trs 0 0\nv a =\n\tp 0 0 0\nv b =\n\tp 1 0 0\nv c =\n\tp 1 1 0\no floor\nm shiny\nf a b c\no\no wall\nm matte\nf a c b\no\n' \
    >shiny2.mgf
"$radiosity" scenes --info shiny2.mgf --json >shiny2.json 2>/dev/null
check "rd + rs over 1: rd scaled to 0.9 / 1.1, and a material that drops rs keeps rd 0.9" python3 -c '
import json, sys
m = {x["name"]: x["reflectance"] for x in json.load(open("shiny2.json"))["materials"]}
sys.exit(0 if all(abs(v - 0.9 / 1.1) < 1e-9 for v in m["shiny"]) and
         all(abs(v - 0.9) < 1e-9 for v in m["matte"]) else 1)' || cat shiny2.json >&2

# Unknown entities are skipped with one warning, as MGF's own parser does (RenderPark's
# office1/graz.mgf has a path name on a line of its own, its hospital a vertex missing its p).
printf 'm x =\n\trd 0.5\nfrobnicate 1 2\n/usr/people/x.rad\nv a =\n\tp 0 0 0\nv b =\n\tp 1 0 0\nv c =\n\tp 1 1 0\nf a b c\n' \
    >unknown.mgf
"$radiosity" scenes --info unknown.mgf >/dev/null 2>unknown.err
check "unknown entities are skipped (exit 0)" test $? -eq 0
check "unknown entities: one warning, at the first" \
    test "$(grep -c 'unknown MGF entity' unknown.err)" = 1 -a \
    "$(grep -c "unknown.mgf:3: unknown MGF entity 'frobnicate' skipped (2 unknown entities" unknown.err)" = 1 \
    || cat unknown.err >&2

# Colours: a spectrum with negative samples is read (RenderPark's Materials/illums.mgf: the CIE
# daylight components), a chromaticity with y = 0 is black where a material uses it, with a
# warning (RenderPark's hospital/blokken2.mgf: 'cxy 0.4 0' for a lamp), and both as RenderPark.
printf 'c day =\n\tcspec 400 700 6 6 6 5 5 5 -0.5\nc purple =\n\tcxy 0.4 0\nm x =\n\tc day\n\trd 0.5\nm lamp =\n\tc purple\n\ted 100\nv a =\n\tp 0 0 0\nv b =\n\tp 1 0 0\nv c =\n\tp 1 1 0\no floor\nm x\nf a b c\no\no light\nm lamp\nf a c b\no\n' \
    >colours.mgf
"$radiosity" scenes --info colours.mgf --json >colours.json 2>colours.err
check "colours: a spectrum with negative samples, a chromaticity with y = 0 (exit 0)" test $? -eq 0
check "colours: the spectrum is a bluish reflectance of luminance 0.5, the y = 0 lamp is black" python3 -c '
import json, sys
m = {x["name"]: x for x in json.load(open("colours.json"))["materials"]}
r = m["x"]["reflectance"]; y = 0.2126 * r[0] + 0.7152 * r[1] + 0.0722 * r[2]
sys.exit(0 if r[2] > r[0] and abs(y - 0.5) < 0.02 and m["lamp"]["emission"] == [0, 0, 0] else 1)' \
    || cat colours.json >&2
check "colours: the black lamp is warned about" \
    grep -q "colours.mgf:10: colour 'purple' has no luminance: the emission of material 'lamp' is read as black" \
    colours.err || cat colours.err >&2

# Arrays (xf -a, i FILE -a): copy (i, j) is the transform before the first -a, then the one
# after it i times, then the one after the second j times (MGF 2.0, RenderPark's reading).
cat >arrays.mgf <<'MGF'
m grey =
	rd 0.5
o row
xf -t 10 0 0 -a 3 -t 2 0 0
i parts/square.mgf
xf
o
o grid
xf -a 2 -t 0 2 0 -a 3 -t 2 0 0
v g0 =
	p 0 0 5
v g1 =
	p 1 0 5
v g2 =
	p 1 1 5
f g0 g1 g2
xf
o
o stack
i parts/square.mgf -rx 90 -a 4 -t 0 0 -1
o
MGF
"$radiosity" scenes --info arrays.mgf --json >arrays.json 2>/dev/null
check "arrays: 3 squares in a row, 6 triangles in a grid, 4 stacked squares, where MGF puts them" python3 -c '
import json, sys
d = json.load(open("arrays.json")); a = {s["name"]: s["area"] for s in d["surfaces"]}
ok = abs(a["row"] - 3) < 1e-9 and abs(a["grid"] - 3) < 1e-9 and abs(a["stack"] - 4) < 1e-9
ok = ok and d["bounds"]["min"] == [0, 0, -3] and d["bounds"]["max"] == [15, 3, 5]
sys.exit(0 if ok else 1)' || cat arrays.json >&2
# Non-convex faces and faces of more than 64 corners: a few convex pieces (scene/polygon_cut.h),
# their areas kept: an L (2 quads), a gear of 100 teeth (its teeth and a 200-gon core, split into
# a 64-gon and 64 caps), a convex 100-gon (a 64-gon and 36 caps; was refused: "polygon too
# large", then fanned as 64-gons around one corner).
python3 - <<'PY'
import math
out = ["m grey =", "\tc", "\trd 0.5"]
def face(name, points):
    names = []
    for i, (x, y) in enumerate(points):
        out.append("v %s%d =\n\tp %.9g %.9g 0" % (name, i, x, y))
        names.append("%s%d" % (name, i))
    out.append("o %s\nf %s\no" % (name, " ".join(names)))
face("ell", [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)])
gear, pitch = [], 2 * math.pi / 100
for k in range(100):
    for a, r in ((0, 0.8), (0.125, 1), (0.375, 1), (0.5, 0.8)):
        gear.append((5 + r * math.cos((k + a) * pitch), r * math.sin((k + a) * pitch)))
face("gear", gear)
face("disk", [(10 + math.cos(2 * math.pi * k / 100), math.sin(2 * math.pi * k / 100)) for k in range(100)])
open("ngons.mgf", "w").write("\n".join(out) + "\n")
PY
"$radiosity" scenes --info ngons.mgf --json >ngons.json 2>/dev/null
check "non-convex and 100-corner faces: areas kept, in 2 + 165 + 37 convex pieces" python3 -c '
import json, sys
d = json.load(open("ngons.json")); a = {s["name"]: s["area"] for s in d["surfaces"]}
ok = abs(a["ell"] - 3) < 1e-6 and abs(a["gear"] - 2.4188222) < 1e-6 and abs(a["disk"] - 3.1395260) < 1e-6
sys.exit(0 if ok and d["polygons"] == 204 else 1)' || cat ngons.json >&2
head -c 300 /dev/urandom >garbage.mgf
expect_exit 1 'garbage.mgf' -- "$radiosity" solve garbage.mgf

finish
