#!/usr/bin/env bash
# cli_adversarial.sh - hostile files, special files and option values (docs/errors.md): each gets
# the documented exit status and one line on stderr, in bounded time, and leaves nothing
# behind (no output, no temporary, no core file) and replaces nothing.
# tests/assimp-sample/ holds small files from assimp's test/models (BSD licence,
# LICENSE.assimp) that crash assimp 5.2.5; the import runs in a child process, so each is one
# line. scripts/assimp-corpus.sh runs the whole assimp corpus by hand.
# Special files are made here (FIFOs with mkfifo, symlinks); the only device read is /dev/zero.
# Usage: cli_adversarial.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"
cd "$work" || exit 1
sample=$source_dir/tests/assimp-sample

# expect STATUS PATTERN -- COMMAND...: lib_cli.sh's expect_exit under a time limit; warnings
# ('radiosity: warning:') aside, one line.
expect() {
    local want=$1 pattern=$2; shift 3
    timeout -k 5 60 "$@" >out 2>err
    local got=$?
    check "exit $want (got $got) from $*" test "$got" -eq "$want"
    [[ -z $pattern ]] || check "message /$pattern/ from $*" grep -q -- "$pattern" err
    check "one line on stderr from $*" test "$(grep -vEc '^radiosity: (warning:|\[)' err)" -le 1
    grep -q -- "$pattern" err || sed 's/^/    stderr: /' err | head -n 5 >&2
    rm -f out err
}
# Nothing in the working directory but what the test made (keep.*).
nothing_left() { check "nothing left behind after $1" test -z "$(ls | grep -v '^keep')"; }

# 1. Files that crash assimp: one line naming the signal, no core file.
for file in "$sample"/*; do
    case $(basename "$file") in
    LICENSE*) continue ;;
    ok-*) expect 0 '' -- "$radiosity" solve "$file" --quiet --threads 1 --elements 100 ;;
    # These two make assimp read past an array: whether that faults depends on the memory
    # layout (in the sanitizer build it reads garbage and finds no faces). Either way: one line.
    Overflowing*Index.md5mesh)
        expect 1 'assimp could not read it (it crashed: SIG\|the scene has no faces' -- \
            "$radiosity" solve "$file" --quiet --threads 1 ;;
    *) expect 1 "assimp could not read it (it crashed: SIG" -- \
           "$radiosity" solve "$file" --quiet --threads 1 ;;
    esac
    nothing_left "$(basename "$file")"
done

# 2. Memory: counts that claim far more than the file holds (the import child's address-space
# limit, not a pre-check, stops them).
# (binary: an ASCII row that short is refused by the pre-check, see section 8)
{ printf 'ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n'
  printf '\0\0\0\0\0\0\0\0\0\0\0\0\0\0\200\77\0\0\0\0\0\0\0\0\0\0\0\0\0\0\200\77\0\0\0\0'
  printf '\0\302\353\13\0\0\0\0\1\0\0\0\2\0\0\0'; } >keep-face.ply
printf 'OFF\n350000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >keep-huge.off
# (Not under ASan: it maps terabytes of shadow memory, so the child gets no address-space limit.)
if ! nm -D "$radiosity" 2>/dev/null | grep -q __asan_init; then
    expect 1 "exceeded the memory budget of 8.0 MiB" -- "$radiosity" solve keep-face.ply --max-memory 8
    expect 1 "exceeded the memory budget of 2048.0 MiB" -- "$radiosity" solve keep-huge.off
fi
nothing_left "budget overruns"

# 3. Special files as scenes: refused before they are read, without blocking.
mkfifo keep-fifo.obj
expect 1 "keep-fifo.obj: is a FIFO (pipe), not a regular file" -- "$radiosity" solve keep-fifo.obj
# A patch system is read once, so a FIFO will do; with no writer it reads as empty at once.
mkfifo keep-fifo.ffm
expect 1 "keep-fifo.ffm: empty file" -- "$radiosity" render keep-fifo.ffm -o x.png
mkfifo keep-fed.ffm
(printf 'patch a area 1 reflectance 0.5 emission 1\n' >keep-fed.ffm &)
expect 0 '' -- "$radiosity" solve keep-fed.ffm --quiet
mkdir keep-dir.ffm
expect 1 "keep-dir.ffm: is a directory" -- "$radiosity" solve keep-dir.ffm
ln -s /dev/zero keep-zero.glb
ln -s /dev/zero keep-zero.gltf
ln -s /dev/zero keep-zero.obj
for name in keep-zero.glb keep-zero.gltf keep-zero.obj; do
    expect 1 "$name: is a character device, not a regular file" -- "$radiosity" solve "$name"
done
mkdir keep-dir.obj
expect 1 "keep-dir.obj: is a directory, not a regular file" -- "$radiosity" solve keep-dir.obj
ln -s "$source_dir/scenes/room.obj" keep-link.obj
expect 0 '' -- "$radiosity" solve keep-link.obj --quiet --threads 1 --elements 100
nothing_left "special files"
check "the FIFO is still a FIFO" test -p keep-fifo.obj

# 4. Option values: one rule, a usage error (2), in every command.
for command in "solve cornell" "render cornell -o x.png" "pathtrace cornell -o x.png" \
               "formfactors cornell" "bake cornell -o x.ply"; do
    for bad in "--threads 0" "--threads 1000000" "--threads 1000000000" "--max-memory 0" \
               "--max-memory 1e-9"; do
        # shellcheck disable=SC2086
        expect 2 "${bad%% *} wants" -- "$radiosity" $command $bad
    done
done
expect 2 "solve: --tolerance must be positive" -- "$radiosity" solve four-walls --tolerance -1
expect 2 "solve: --omega must be in (0, 2), not 2" -- "$radiosity" solve four-walls --omega 2
expect 2 "render: --omega must be in (0, 2), not 2" -- "$radiosity" render cornell --omega 2 -o x.png
expect 2 "render: --discontinuity must be 0 or 1, not 2" -- "$radiosity" render cornell --discontinuity 2 -o x.png
nothing_left "option values"

# The built-in geometric scenes render with their own cameras.
for scene in two-squares unit-cube; do
    expect 0 '' -- "$radiosity" render "$scene" --quiet --threads 1 --width 16 --height 16 \
        --elements 50 -o "keep-$scene.pfm"
    check "$scene rendered" test -s "keep-$scene.pfm"
done

# 5. Finite inputs whose products are not.
printf 'patch a area 1e200 reflectance 0.5 emission 1e200\npatch b area 1 reflectance 0.5 emission 0\nff a b 0.5\nff b a 0.5\n' >keep-power.ffm
expect 1 "keep-power.ffm: surface 'a': its emitted power (area 1e+200 times its emission) is not a finite number" -- \
    "$radiosity" solve keep-power.ffm
printf 'v 0 0 0\nv 1e160 0 0\nv 0 1e160 0\nf 1 2 3\n' >keep-float.obj
expect 1 "not a finite number in single precision" -- "$radiosity" solve keep-float.obj
nothing_left "overflowing products"

expect 1 "bake: a scale of 1e+308 makes the mesh's coordinates" -- \
    "$radiosity" bake unit-cube --elements 24 --scale 1e308 -o x.gltf
nothing_left "bake --scale 1e308"

# 6. Standard output that cannot be written: an error, not exit 0.
timeout 60 "$radiosity" solve four-walls --json >&- 2>err
check "closed stdout: exit 1" test $? -eq 1
check "closed stdout: message" grep -q "cannot write to standard output" err
rm -f err
nothing_left "closed stdout"

# 7. Names that are not UTF-8 (Latin-1, a lone continuation, an overlong NUL, a surrogate):
# every JSON writer replaces each bad byte with U+FFFD and keeps the good characters.
printf 'o caf\xe9\xff\xc0\x80\xed\xa0\x80ok\xc3\xa9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n' >keep-latin1.obj
valid_json() { # FILE KEY: strict UTF-8 JSON, and the name found under KEY
    python3 -c 'import json,sys; d=json.load(open(sys.argv[1],encoding="utf-8",errors="strict")); n=[x.get("name") for x in d[sys.argv[2]]]; sys.exit(0 if "caf\ufffd\ufffd\ufffd\ufffd\ufffd\ufffd\ufffdok\u00e9" in n else 1)' "$1" "$2"
}
"$radiosity" solve keep-latin1.obj --json --quiet >keep-solve.json 2>/dev/null
check "solve --json: valid UTF-8 JSON with the name's good characters" valid_json keep-solve.json patches
"$radiosity" formfactors keep-latin1.obj --json >keep-ff.json 2>/dev/null
check "formfactors --json: valid UTF-8 JSON" valid_json keep-ff.json surfaces
"$radiosity" bake keep-latin1.obj --quiet -o keep-bake.gltf 2>/dev/null
check "bake glTF: valid UTF-8 JSON" valid_json keep-bake.gltf nodes
check "bake glTF: valid UTF-8 JSON (meshes)" valid_json keep-bake.gltf meshes
nothing_left "names that are not UTF-8"

# 8. Files assimp reads wrong without a word: each is refused with its reason (or read right).
bom=$'\xef\xbb\xbf'
{ printf '%s' "$bom"; grep -v '^#' "$source_dir/scenes/room.obj"; } >keep-bom.obj
expect 1 "keep-bom.obj:1: a UTF-8 byte-order mark before the first statement hides it" -- \
    "$radiosity" solve keep-bom.obj
{ printf '%s# a comment first is safe\n' "$bom"; grep -v '^#' "$source_dir/scenes/room.obj"; } >keep-bom-comment.obj
expect 0 '' -- "$radiosity" solve keep-bom-comment.obj --quiet --threads 1 --elements 100
printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >keep-few.ply
expect 1 "keep-few.ply: the PLY file ends after 0 of the 1 'face' rows its header promises" -- \
    "$radiosity" solve keep-few.ply
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n' >keep-short-row.ply
expect 1 "keep-short-row.ply:13: this 'face' row has fewer values" -- "$radiosity" solve keep-short-row.ply
# Blender 2.47 wrote a free text line into the header; assimp skips it, and so do we.
printf 'ply\nformat ascii 1.0\nCreated by Blender3D 247 - www.blender.org, source file: \nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >keep-blender.ply
expect 0 '' -- "$radiosity" solve keep-blender.ply --quiet --threads 1
gltf() { # FILE INDICES ROTATION: a unit square as a glTF with an embedded buffer
    python3 - "$@" <<'PY'
import base64, json, struct, sys
path, indices, rotation = sys.argv[1], json.loads(sys.argv[2]), json.loads(sys.argv[3])
vb = b''.join(struct.pack('<3f', *p) for p in [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)])
ib = b''.join(struct.pack('<H', i) for i in indices)
node = {"mesh": 0, "name": "square"}
if rotation is not None: node["rotation"] = rotation
g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [node],
     "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
     "buffers": [{"byteLength": len(vb + ib), "uri": "data:application/octet-stream;base64," +
                  base64.b64encode(vb + ib).decode()}],
     "bufferViews": [{"buffer": 0, "byteLength": len(vb)},
                     {"buffer": 0, "byteOffset": len(vb), "byteLength": len(ib)}],
     "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                    "min": [0, 0, 0], "max": [1, 1, 0]},
                   {"bufferView": 1, "componentType": 5123, "count": len(indices), "type": "SCALAR"}]}
json.dump(g, open(path, 'w'))
PY
}
gltf keep-square.gltf '[0,1,2,1,3,2]' 'null'
expect 0 '' -- "$radiosity" solve keep-square.gltf --quiet --threads 1
gltf keep-past.gltf '[0,1,2,1,7,2]' 'null'
expect 1 "keep-past.gltf: faces with vertex indices past their POSITION accessor" -- \
    "$radiosity" solve keep-past.gltf
gltf keep-zero-rotation.gltf '[0,1,2,1,3,2]' '[0,0,0,0]'
expect 1 "keep-zero-rotation.gltf: node 0 ('square') has a rotation of length 0" -- \
    "$radiosity" solve keep-zero-rotation.gltf
head -c 600 keep-square.gltf >keep-cut.gltf
expect 1 "keep-cut.gltf: assimp cannot read it: its glTF JSON is cut short or damaged" -- "$radiosity" solve keep-cut.gltf
# Binary files of formats this assimp lacks: not OBJ syntax errors.
for name in keep-bin.max keep-bin.usdc keep-bin.m3d; do
    printf '3DMO\0\1\2\3\nl 1\nf 9 9 9\nv 1\n' >"$name"
    expect 1 "$name: not a scene format assimp can read" -- "$radiosity" solve "$name"
done
nothing_left "files assimp reads wrong"

finish
