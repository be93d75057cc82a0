#!/usr/bin/env bash
# cli_scene_files.sh - no output replaces a file the scene was read from (issue 13): the import
# records every file it opens (assimp's reads through a recording aiFileIO, textures, MGF
# includes, IES profiles; rad_scene_file) and every command refuses, with one line and exit 2,
# an output that is one of them, or whose companion is (bake's FILE.bin beside FILE.gltf,
# export's FILE.mtl beside FILE.obj). The file is left as it was and nothing new is written.
# Usage: cli_scene_files.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"
cd "$work" || exit 1

# A textured glTF room with its buffer in a file of its own (buffer.bin) and its texture in
# checker.png; an OBJ room whose material library is named out.mtl; an MGF file that includes
# the Cornell box.
python3 "$source_dir/scripts/make_textured_room.py" textured.gltf >/dev/null
python3 - <<'PY'
import base64, json
gltf = json.load(open("textured.gltf"))
buffer = gltf["buffers"][0]
open("buffer.bin", "wb").write(base64.b64decode(buffer["uri"].split(",", 1)[1]))
buffer["uri"] = "buffer.bin"
json.dump(gltf, open("textured.gltf", "w"))
PY
cat >room.obj <<'OBJ'
mtllib out.mtl
v 0 0 0
v 0 0 1
v 1 0 1
v 1 0 0
v 0 1 0
v 1 1 0
v 1 1 1
v 0 1 1
usemtl white
f 1 2 3 4
usemtl lamp
f 5 6 7 8
OBJ
printf 'newmtl white\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 1 1 1\n' >out.mtl
printf 'm white =\n\trd 0.5\nv a =\n\tp 0 0 0\nv b =\n\tp 1 0 0\nv c =\n\tp 1 1 0\no floor\nf a b c\no\n' \
    >box.mgf
echo "i box.mgf" >outer.mgf
md5sum buffer.bin checker.png out.mtl box.mgf textured.gltf >before.md5

refused() { # COMMAND...: exit 2, one line naming the output as an input
    expect_exit 2 "is the input" -- "$radiosity" "$@"
}
small=(--width 8 --height 8 --quiet)
refused render textured.gltf -o checker.png "${small[@]}" --elements 50
refused pathtrace textured.gltf -o checker.png "${small[@]}" --spp 1
refused photonmap textured.gltf -o checker.png "${small[@]}" --photons 1000
refused solve textured.gltf --log buffer.bin --quiet --elements 50
refused solve room.obj --save out.mtl --quiet --elements 50
refused bake textured.gltf -o buffer.gltf --quiet --elements 50 # would write buffer.bin
refused scenes --export room.obj out.obj # would write out.mtl
refused solve outer.mgf --log box.mgf --quiet --elements 50
# A snapshot named as the scene's texture: the solve stops there and the texture stays.
mkdir -p snap
cp checker.png snap/snapshot-000001.png
python3 - <<'PY'
import json
gltf = json.load(open("textured.gltf"))
gltf["buffers"][0]["uri"] = "../buffer.bin"
for image in gltf["images"]:
    image["uri"] = "snapshot-000001.png"
json.dump(gltf, open("snap/room.gltf", "w"))
PY
(cd snap && md5sum snapshot-000001.png >../snap.md5)
refused solve snap/room.gltf --snapshots snap --snapshot-every 1 --quiet --elements 50 \
    --width 8 --height 8
check "the texture named as a snapshot is unchanged" \
    sh -c 'cd snap && md5sum --quiet -c ../snap.md5'
check "no input changed" md5sum --quiet -c before.md5
check "nothing new written" test ! -e buffer.gltf -a ! -e out.obj
check "no temporary left" test -z "$(find . -name '*.tmp-*')"
# The same outputs elsewhere are fine, and so is a file beside the scene it did not read.
"$radiosity" scenes --export room.obj copy/room.obj >/dev/null 2>&1 || mkdir copy
check "export beside another mtl" "$radiosity" scenes --export room.obj copy/room.obj
check "the export's own mtl" test -s copy/room.mtl
finish
