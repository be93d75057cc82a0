#!/usr/bin/env bash
# cli_geometry_errors.sh - bad scene files through `radiosity solve`: each one a single line
# "radiosity: FILE: ..." on stderr and exit status 1, never a crash or a hang; degenerate faces
# and a scene without emitters only warn (exit 0).
# Usage: cli_geometry_errors.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"
cd "$work" || exit 1

run() { # run FILE [options]: solve with a time limit; status in $status, output in out/err
    timeout 60 "$radiosity" solve "$@" --elements 50 --json >out 2>err
    status=$?
}
# refused FILE PATTERN: exit 1, one line "radiosity: FILE...PATTERN" on stderr, nothing on stdout.
refused() {
    local file=$1 pattern=$2
    run "$file"
    check "$file: exit 1 (got $status)" test "$status" -eq 1
    check "$file: one line on stderr" test "$(grep -vc '^radiosity: \[' err)" -eq 1
    check "$file: message /$pattern/ (got: $(head -c 200 err))" grep -q "^radiosity: .*$pattern" err
    check "$file: no output" test ! -s out
}
quad='v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n'

# A file that is not there.
refused missing.obj 'missing.obj: No such file or directory'

# A format assimp cannot read, and files it cannot parse.
printf 'not a scene at all\n' >noise.xyz
refused noise.xyz 'noise.xyz: not a scene format'
printf 'hello\n' >tiny.obj
refused tiny.obj 'tiny.obj: assimp cannot read it'
head -c 3000 /dev/zero | tr '\0' '\377' >binary.obj
refused binary.obj 'binary.obj'
printf '{"asset": {"version": "2.0"}, "meshes": [' >broken.gltf
refused broken.gltf 'broken.gltf: assimp cannot read it'
head -c 300 "$source_dir/scenes/lamp-room.glb" >cut.glb
refused cut.glb 'cut.glb: the binary glTF header says'
head -c 200 "$source_dir/scenes/square.ply" >cut.ply
refused cut.ply 'cut.ply: the PLY header has no end_header line'
sed 's/element vertex 6/element vertex 600000000/' "$source_dir/scenes/square.ply" >big.ply
refused big.ply 'big.ply: the PLY header promises'
printf "o bad\n${quad}f 1 2 3 9\n" >index.obj
refused index.obj 'index.obj'

# Empty scenes: no faces at all, or only points and lines.
printf "# corners, and no faces\n${quad}" >empty.obj
refused empty.obj 'empty.obj: the scene has no faces'
printf "# lines only\n${quad}l 1 2\nl 2 3\np 4\n" >lines.obj
refused lines.obj 'lines.obj: the scene has no faces (only points and lines)'
printf '{"asset": {"version": "2.0"}, "scenes": [{"nodes": []}], "scene": 0}' >empty.gltf
refused empty.gltf 'empty.gltf'

# Coordinates that are not numbers.
printf 'o broken\nv 0 0 0\nv nan 0 0\nv 1 1 0\nf 1 2 3\n' >nan.obj
refused nan.obj "nan.obj: object 'broken': vertex 1 has a coordinate that is not a finite number"
printf 'o broken\nv 0 0 0\nv 1 0 0\nv 1 -inf 0\nf 1 2 3\n' >inf.obj
refused inf.obj 'inf.obj: .*not a finite number'

# Degenerate faces: all of them is an error; some of them a warning with the count.
printf 'o flat\nv 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\nf 2 2 2\n' >degenerate.obj
refused degenerate.obj 'degenerate.obj: every face is degenerate (3 faces'
printf "mtllib lamp.mtl\nusemtl lamp\no lamp\n${quad}f 1 2 3 4\nf 1 2 2\nv 2 0 0\nf 1 2 5\n" >some.obj
printf 'newmtl lamp\nKd 0.5 0.5 0.5\nKe 1 1 1\n' >lamp.mtl
run some.obj
check "some.obj: exit 0" test "$status" -eq 0
check "some.obj: warning with the count" grep -q '^radiosity: warning: some.obj: dropped 2 degenerate faces' err
# The quad's area as a number (its elements sum it to within rounding, not always to 1 exactly).
lamp_area=$(grep -oE '"name": "lamp", "area": [0-9.e+-]+' out | grep -oE '[0-9.e+-]+$')
check "some.obj: the quad is solved" awk -v a="${lamp_area:-0}" 'BEGIN { exit !(a > 1 - 1e-10 && a < 1 + 1e-10) }'

# Reflectance above 1: kept by the importer, refused when the system is built.
printf 'newmtl bright\nKd 1.2 0.5 0.5\nKe 1 1 1\n' >bright.mtl
printf "mtllib bright.mtl\nusemtl bright\n${quad}f 1 2 3 4\n" >bright.obj
refused bright.obj "bright.obj: material 'bright' has reflectance 1.2, outside \[0, 1\]"
printf 'newmtl dark\nKd 0.5 0.5 0.5\nKe -1 0 0\n' >negative.mtl
printf "mtllib negative.mtl\nusemtl dark\n${quad}f 1 2 3 4\n" >negative.obj
refused negative.obj "negative.obj: material 'dark' has emission -1"

# No emitters: a warning and a black result.
printf "o square\n${quad}f 1 2 3 4\n" >dark.obj
run dark.obj
check "dark.obj: exit 0" test "$status" -eq 0
check "dark.obj: warning" grep -q '^radiosity: warning: dark.obj: nothing emits light; the result will be black' err
check "dark.obj: black" grep -q '"radiosity": \[0, 0, 0\]' out

# An MTL file that is missing: assimp's default material (no emitter), not a failure.
printf "mtllib gone.mtl\nusemtl gone\n${quad}f 1 2 3 4\n" >no-mtl.obj
run no-mtl.obj
check "no-mtl.obj: exit 0" test "$status" -eq 0
check "no-mtl.obj: no emitter" grep -q 'nothing emits light' err

finish
