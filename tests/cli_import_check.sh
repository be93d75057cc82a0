#!/usr/bin/env bash
# cli_import_check.sh - scene files that crash or hang assimp 5.2.5 (found by fuzz_import) are
# refused by the checks of src/scene/import_check.c before assimp reads them: one line
# "radiosity: FILE:LINE: ..." and exit status 1, never an abort; valid polylines still solve.
# Usage: cli_import_check.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"
cd "$work" || exit 1

run() { # run FILE: solve with a time limit; status in $status, output in out/err
    timeout 60 "$radiosity" solve "$1" --elements 20 --json >out 2>err
    status=$?
}
refused() { # refused FILE PATTERN: exit 1, one line "radiosity: ...PATTERN", nothing on stdout
    local file=$1 pattern=$2
    run "$file"
    check "$file: exit 1 (got $status)" test "$status" -eq 1
    check "$file: one line on stderr" test "$(wc -l <err)" -eq 1
    check "$file: message /$pattern/ (got: $(head -c 200 err))" grep -q "^radiosity: .*$pattern" err
    check "$file: no output" test ! -s out
}

# Two one-vertex polylines, then one of three: assimp writes past its vertex array (glibc
# aborts with "malloc assertion failure").
printf 'v 0 0 0\nl 1\nl 1\nl 1 1 1\n' >polyline.obj
refused polyline.obj "polyline.obj:2: a polyline ('l') needs at least two vertex indices"
# The same in a file whose name assimp does not know: it would still take it for OBJ.
cp polyline.obj polyline.data
refused polyline.data 'polyline.data:2: a polyline'
# "lod" (an OBJ statement assimp reads as a polyline)
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nlod 1\nl 1\nl 1 2 3\nf 1 2 3\n' >lod.obj
refused lod.obj "lod.obj:4: assimp reads 'lod' as a polyline"
# A continuation backslash without a newline after it (assimp searches past its buffer for one).
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3 \\' >continued.obj
refused continued.obj 'continued.obj:4: a line continuation'
# A PLY "End_header": assimp matches it case by case and loops forever.
sed 's/^end_header/End_header/' "$source_dir/scenes/square.ply" >end-case.ply
refused end-case.ply "end-case.ply:[0-9]*: 'End_header' must be written end_header"

# Polylines of two or more vertices, and the sample scenes, still solve.
printf 'o floor\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nl 1 2\nl 1/1 2/1 3/1\nl -1 -2\nf 1 2 3 4\n' >fine.obj
run fine.obj
check "fine.obj: exit 0 (got $status: $(head -c 200 err))" test "$status" -eq 0
check "fine.obj: one surface" grep -q '"floor"' out
for scene in "$source_dir"/scenes/*.obj "$source_dir"/scenes/*.ply; do
    run "$scene"
    check "$(basename "$scene"): exit 0 (got $status: $(head -c 200 err))" test "$status" -eq 0
done
finish
