#!/usr/bin/env bash
# cli_errors.sh - one test per row of docs/errors.md: every class of bad input gets one clear
# line on stderr, the documented exit status, and no output file (whole or half-written).
# A row passes when all of its checks pass; the closing line counts rows.
# Usage: cli_errors.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"
cd "$work" || exit 1

rows_passed=0 rows_failed=0 row_ok=1 row_name=
row() { # row NAME: starts a row (closing the previous one)
    end_row
    row_name=$1 row_ok=1 row_start=$SECONDS
}
end_row() {
    [[ -z $row_name ]] && return
    if ((row_ok)); then rows_passed=$((rows_passed + 1)); echo "ok: $row_name ($((SECONDS - row_start)) s)"
    else rows_failed=$((rows_failed + 1)); echo "FAILED ROW: $row_name" >&2; fi
    row_name=
}
check() { # check NAME CONDITION...: here a failed check fails its row (replaces lib_cli.sh's)
    local name=$1; shift
    if ! "$@"; then row_ok=0; echo "  failed: $name" >&2; fi
}
# expect STATUS PATTERN -- COMMAND...: the exit status, the message, and one line on stderr
# (warnings before it aside: lines starting 'radiosity: warning:').
expect() {
    local want=$1 pattern=$2; shift 3
    timeout 120 "$@" >out 2>err
    local got=$?
    check "exit $want (got $got) from: $*" test "$got" -eq "$want"
    check "message /$pattern/ from: $*" grep -q -- "$pattern" err
    check "one error line from: $*" test "$(grep -vEc '^radiosity: (warning:|\[)' err)" -le 1
    if ! grep -q -- "$pattern" err; then sed 's/^/    stderr: /' err | head -n 5 >&2; fi
}
# Nothing in the directory but the inputs a row made on purpose (named in.* or keep.*).
no_outputs() { test -z "$(ls | grep -v -e '^in\.' -e '^in-' -e '^keep' -e '^out$' -e '^err$')"; }
bytes() { python3 -c "import sys; sys.stdout.buffer.write(bytes.fromhex(sys.argv[1]))" "$1"; }

# A small linear image for compare.
"$radiosity" pathtrace cornell --width 8 --height 8 --spp 1 --quiet -o keep.pfm

row "missing file"
expect 1 'in.missing.ffm: No such file or directory' -- "$radiosity" solve in.missing.ffm
expect 1 'in.missing.obj: No such file or directory' -- "$radiosity" render in.missing.obj -o x.png
expect 1 'in.missing.pfm: cannot open' -- "$radiosity" compare in.missing.pfm keep.pfm
expect 1 'in.missing.sol' -- "$radiosity" solve four-walls --resume in.missing.sol
check "no output" no_outputs

row "empty file"
: >in.empty.ffm; : >in.empty.obj; : >in.empty.pfm; : >in.empty.sol
expect 1 'in.empty.ffm: empty file' -- "$radiosity" solve in.empty.ffm
expect 1 'in.empty.obj' -- "$radiosity" solve in.empty.obj
expect 1 'in.empty.pfm: not a PFM file' -- "$radiosity" compare in.empty.pfm keep.pfm
expect 1 'in.empty.sol: not a radiosity solution file' -- \
    "$radiosity" solve four-walls --resume in.empty.sol
check "no output" no_outputs

row "truncated file"
printf 'patch a area 1 reflectance 0.5 emission 1\npatch b ar' >in.truncated.ffm
head -c 300 "$source_dir/scenes/lamp-room.glb" >in.truncated.glb
head -c 40 keep.pfm >in.truncated.pfm
"$radiosity" solve four-walls --quiet --save keep.sol >/dev/null
head -c 100 keep.sol >in.truncated.sol
# A PLY header cut before end_header (assimp would wait forever); "ply," is still PLY to it.
printf 'ply,\nformat ascii 1.0\nelement vertex 3\nproperty float x\n' >in.truncated.ply
expect 1 'in.truncated.ply: the PLY header has no end_header line' -- \
    "$radiosity" solve in.truncated.ply
expect 1 'in.truncated.ffm:2: ' -- "$radiosity" solve in.truncated.ffm
expect 1 'in.truncated.glb' -- "$radiosity" solve in.truncated.glb
expect 1 'in.truncated.pfm: PFM data ends early' -- "$radiosity" compare in.truncated.pfm keep.pfm
expect 1 'in.truncated.sol: truncated solution file' -- \
    "$radiosity" solve four-walls --resume in.truncated.sol
check "no output" no_outputs

row "binary garbage"
garbage=$(python3 -c "import random; r = random.Random(7); print(bytes(r.randrange(256) for _ in range(512)).hex())")
for ext in ffm obj hdr sol; do bytes "$garbage" >in.garbage.$ext; done
expect 1 'in.garbage.ffm:1: binary data' -- "$radiosity" solve in.garbage.ffm
expect 1 'in.garbage.obj' -- "$radiosity" solve in.garbage.obj
expect 1 'in.garbage.hdr: not a Radiance HDR file' -- "$radiosity" compare in.garbage.hdr keep.pfm
expect 1 'in.garbage.sol: not a radiosity solution file' -- \
    "$radiosity" solve four-walls --resume in.garbage.sol
check "no output" no_outputs

row "NaN or Inf"
printf 'patch a area nan reflectance 0.5 emission 1\n' >in.nan.ffm
printf 'patch a area 1 reflectance 0.5 emission inf\n' >in.inf.ffm
printf 'v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n' >in.nan.obj
python3 -c "import struct, sys; sys.stdout.buffer.write(b'PF\n2 1\n-1.0\n' + struct.pack('<6f', float('nan'), 1, 1, 1, 1, 1))" >in.nan.pfm
python3 -c "import struct, sys; sys.stdout.buffer.write(b'PF\n2 1\n-1.0\n' + struct.pack('<6f', 1, 1, 1, 1, 1, 1))" >in.ones.pfm
expect 1 "in.nan.ffm:1: area: 'nan' is not a finite number" -- "$radiosity" solve in.nan.ffm
expect 1 "in.inf.ffm:1: emission: 'inf' is not a finite number" -- "$radiosity" solve in.inf.ffm
expect 1 'in.nan.obj: .*not a finite number' -- "$radiosity" solve in.nan.obj
expect 1 'not finite at pixel (0, 0)' -- "$radiosity" compare in.nan.pfm in.ones.pfm
expect 2 "tolerance wants a number, not 'nan'" -- "$radiosity" solve four-walls --tolerance nan
expect 2 "eye wants X,Y,Z, not 'inf,0,0'" -- "$radiosity" render cornell --eye inf,0,0 -o x.png
check "no output" no_outputs

row "degenerate geometry"
printf 'v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n' >in.degenerate.obj
printf 'newmtl light\nKd 0.5 0.5 0.5\nKe 1 1 1\n' >in-some.mtl
printf 'mtllib in-some.mtl\nusemtl light\nv 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n' \
    >in.some-degenerate.obj
expect 1 'in.degenerate.obj: every face is degenerate' -- "$radiosity" solve in.degenerate.obj
timeout 120 "$radiosity" solve in.some-degenerate.obj --elements 50 >out 2>err
check "some degenerate faces: exit 0" test $? -eq 0
check "some degenerate faces: a warning" grep -q 'warning: .*dropped 1 degenerate face' err
check "no output" no_outputs

row "reflectance 1 or more"
printf 'patch a area 1 reflectance 1.5 emission 1\n' >in.bright.ffm
printf 'newmtl white\nKd 1.5 0.5 0.5\n' >in-bright.mtl
printf 'mtllib in-bright.mtl\nusemtl white\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >in.bright.obj
printf 'patch a area 1 reflectance 1 emission 1\npatch b area 1 reflectance 1\nff a b 1\nff b a 1\n' \
    >in.lossless.ffm
expect 1 "in.bright.ffm:1: reflectance of 'a' must be in \[0, 1\]" -- "$radiosity" solve in.bright.ffm
expect 1 "in.bright.obj: material 'white' has reflectance 1.5, outside \[0, 1\]" -- \
    "$radiosity" solve in.bright.obj
expect 1 'the radiosity system is singular' -- "$radiosity" solve in.lossless.ffm --solver direct
check "reflectance 1 warns" grep -q 'warning: .*reflectance of 1 loses no energy' err
timeout 120 "$radiosity" solve in.lossless.ffm --solver shooting --iterations 50 >out 2>err
check "reflectance 1, iterative: exit 0" test $? -eq 0
check "reflectance 1, iterative: not converged" grep -q 'not converged' out
check "no output" no_outputs

row "negative emission"
printf 'patch a area 1 reflectance 0.5 emission -1\n' >in.negative.ffm
printf 'newmtl dark\nKd 0.5 0.5 0.5\nKe -1 0 0\n' >in-negative.mtl
printf 'mtllib in-negative.mtl\nusemtl dark\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >in.negative.obj
expect 1 "in.negative.ffm:1: emission of 'a' must not be negative" -- "$radiosity" solve in.negative.ffm
expect 1 "in.negative.obj: material 'dark' has emission -1; it must be >= 0" -- \
    "$radiosity" solve in.negative.obj
check "no output" no_outputs

row "no emitters"
printf 'patch a area 1 reflectance 0.5\npatch b area 1 reflectance 0.5\nff a b 0.5\nff b a 0.5\n' \
    >in.dark.ffm
# The Cornell box with its light turned off.
"$radiosity" scenes --export cornell in.dark.obj
sed -i '/^Ke /d' in.dark.mtl
timeout 120 "$radiosity" solve in.dark.ffm --json >out 2>err
check "patch system: exit 0" test $? -eq 0
check "patch system: warns" grep -q 'warning: in.dark.ffm: nothing emits light' err
check "patch system: radiosity 0" grep -q '"radiosity": \[0, 0, 0\]' out
timeout 120 "$radiosity" render in.dark.obj --elements 100 --width 8 --height 8 --quiet -o keep.dark.pfm >out 2>err
check "geometry: exit 0" test $? -eq 0
check "geometry: warns even with --quiet" grep -q 'warning: in.dark.obj: nothing emits light' err
check "geometry: a black image" python3 -c "
import struct, sys
data = open('keep.dark.pfm', 'rb').read()
sys.exit(0 if max(struct.unpack('<192f', data[-768:])) == 0 else 1)"

row "too large for --max-memory"
start=$SECONDS
expect 1 'the mesh needs .* MiB, over the memory budget of 64.0 MiB (--max-memory)' -- \
    "$radiosity" solve cornell --elements 2000000 --max-memory 64
expect 1 'the form-factor matrix .* over the memory budget of 50.0 MiB' -- \
    "$radiosity" solve cornell --elements 20000 --solver jacobi --max-memory 50
expect 1 'the direct solver needs .* over the memory budget of 100.0 MiB' -- \
    "$radiosity" solve cornell --elements 20000 --solver direct --max-memory 100
expect 1 'the image needs 3072.0 MiB, over the memory budget of 100.0 MiB' -- \
    "$radiosity" pathtrace cornell --width 16384 --height 16384 --max-memory 100 -o x.pfm
expect 1 'the mesh needs .* over the memory budget' -- \
    "$radiosity" bake cornell --elements 2000000 --max-memory 64 -o x.ply
# A patch system of 3000 patches (a 150 kB file) needs a 69 MiB matrix.
python3 -c "
for i in range(3000): print('patch p%d area 1 reflectance 0.5 emission 1' % i)" >in.many.ffm
expect 1 'the form-factor matrix of the patch system needs 68.7 MiB, over the memory budget of 16.0 MiB' -- \
    "$radiosity" solve in.many.ffm --max-memory 16
# Files without end stop at the budget too.
ln -s /dev/zero in.endless.ffm
ln -s /dev/zero in.endless.sol
expect 1 'in.endless.ffm needs 16.0 MiB, over the memory budget of 8.0 MiB' -- \
    "$radiosity" solve in.endless.ffm --max-memory 8
expect 1 'in.endless.sol needs 32.0 MiB, over the memory budget of 16.0 MiB' -- \
    "$radiosity" solve four-walls --resume in.endless.sol --max-memory 16
check "refused before the work, not after it (took $((SECONDS - start)) s)" \
    test $((SECONDS - start)) -lt 60
check "no output" no_outputs

row "unwritable output path"
start=$SECONDS
expect 1 'no/such/dir/x.png: cannot write: No such file or directory' -- \
    "$radiosity" render cornell -o no/such/dir/x.png
expect 1 'no/dir/x.pfm: cannot write' -- "$radiosity" pathtrace cornell -o no/dir/x.pfm
expect 1 'no/dir/x.ply: cannot write' -- "$radiosity" bake cornell -o no/dir/x.ply
expect 1 'no/dir/x.sol: cannot write' -- "$radiosity" solve cornell --save no/dir/x.sol
expect 1 'no/dir/d.png: cannot write' -- "$radiosity" compare keep.pfm keep.pfm --diff no/dir/d.png
expect 1 'no/dir/x.obj' -- "$radiosity" scenes --export cornell no/dir/x.obj
mkdir keep.dir
expect 1 'keep.dir: is a directory' -- "$radiosity" solve four-walls --save keep.dir
check "refused before the work (took $((SECONDS - start)) s)" test $((SECONDS - start)) -lt 60
check "no output" no_outputs

row "interrupted run"
# interrupt SECONDS COMMAND...: Ctrl-C (SIGINT) after SECONDS; the exit status is in $status.
interrupt() {
    local after=$1; shift
    timeout 300 "$@" >out 2>err &
    local pid=$!
    sleep "$after"
    kill -INT "$pid" 2>/dev/null
    # timeout(1) passes the signal on to the command it runs, which it starts with SIGINT not
    # ignored (a background job of a script has it ignored, and radiosity would keep it so).
    wait "$pid"
    status=$?
}
# The work is made long (far more Monte Carlo samples than needed: about a second per row, a
# minute in all), so the signal comes in the middle of it however fast the machine.
slow=(cornell --elements 2000 --ff montecarlo --ff-samples 20000)
interrupt 2 "$radiosity" solve "${slow[@]}" --solver jacobi --quiet
check "solve: exit 130 (got $status)" test "$status" -eq 130
check "solve: says interrupted" grep -q '^radiosity: interrupted' err
# The path tracer keeps the image so far (every pixel has at least its first pass) and says how
# many paths it has (before tidy12: no image).
interrupt 2 "$radiosity" pathtrace cornell --spp 100000 --width 8 --height 64 --quiet -o x.png
check "pathtrace: exit 130 (got $status)" test "$status" -eq 130
check "pathtrace: the image so far" test -s x.png
check "pathtrace: says how many paths" \
    grep -Eq '^radiosity: path tracing stopped \(Ctrl-C\) after [0-9.]+ s: [1-9][0-9]*( to [0-9]+)? of 100000 paths per pixel in x.png' err
rm -f x.png
check "pathtrace: no temporary" no_outputs
interrupt 3 "$radiosity" solve "${slow[@]}" --solver shooting --save keep.partial.sol
check "solve --save: exit 130 (got $status)" test "$status" -eq 130
check "solve --save: the solution so far is kept" test -s keep.partial.sol
check "solve --save: says so" grep -q 'saved the solution to keep.partial.sol' err
timeout 300 "$radiosity" solve "${slow[@]}" --solver shooting --quiet \
    --resume keep.partial.sol --iterations 1 >out 2>err
check "the kept solution goes on (--resume)" test $? -eq 0

row "output path equal to an input path"
"$radiosity" scenes --export unit-cube keep.cube.obj
"$radiosity" bake unit-cube --elements 24 --quiet -o keep.cube.ply
cp keep.pfm keep.copy.pfm
sums=$(md5sum keep.cube.obj keep.cube.mtl keep.cube.ply keep.pfm keep.copy.pfm)
expect 2 "the output 'keep.cube.obj' is the input" -- \
    "$radiosity" scenes --export keep.cube.obj keep.cube.obj
expect 2 "the output './keep.cube.ply' is the input" -- \
    "$radiosity" bake keep.cube.ply --quiet -o ./keep.cube.ply
ln -s keep.copy.pfm keep.link.pfm
expect 2 "the output 'keep.link.pfm' is the input 'keep.copy.pfm'" -- \
    "$radiosity" compare keep.pfm keep.copy.pfm --diff keep.link.pfm
expect 2 "the output 'keep.cube.obj' is the input" -- \
    "$radiosity" solve keep.cube.obj --elements 24 --log keep.cube.obj
check "inputs unchanged" test "$sums" = "$(md5sum keep.cube.obj keep.cube.mtl keep.cube.ply keep.pfm keep.copy.pfm)"
# Going on from a solution and saving over it is fine: it is read whole first.
"$radiosity" solve four-walls --quiet --iterations 2 --save keep.again.sol >/dev/null
timeout 120 "$radiosity" solve four-walls --quiet --resume keep.again.sol --save keep.again.sol >out 2>err
check "--resume FILE --save FILE is allowed" test $? -eq 0

row "outputs are whole files with ordinary permissions"
(umask 022 && "$radiosity" pathtrace cornell --width 8 --height 8 --spp 1 --quiet -o keep.mode.pfm)
check "mode 644 under umask 022" test "$(stat -c %a keep.mode.pfm)" = 644
check "no temporaries left" no_outputs

end_row
echo "$rows_passed passed, $rows_failed failed"
test "$rows_failed" -eq 0
