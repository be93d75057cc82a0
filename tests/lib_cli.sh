# lib_cli.sh - what every tests/cli_*.sh shares, sourced first thing:
#     source "$(dirname "$0")/lib_cli.sh" "$@"
# (not a test itself: CMake globs tests/cli_*.sh). With the script's arguments RADIOSITY
# SOURCE_DIR it sets
#     radiosity    the binary, as an absolute path (tests may cd)
#     source_dir   the source tree, absolute
#     work         a fresh temporary directory, removed on exit (read-only parts too)
#     PYTHONPATH   with $work/.python first, where pfm.py is: `from pfm import read_pfm` in a
#                  test's Python reads an image the CLI wrote (see below; a hidden folder, so
#                  that tests listing what a command left in $work do not see it)
# and gives the checks below, which count into `passed` and `failed`. A test ends with `finish`,
# which prints the closing line `N passed, N failed` and fails when any check failed, or when no
# check ran at all.
set -u
if (($# < 2)); then
    echo "usage: $(basename "$0") RADIOSITY SOURCE_DIR" >&2
    exit 2
fi
radiosity=$(realpath "$1")
source_dir=$(realpath "$2")
passed=0 failed=0
work=$(mktemp -d)
trap 'chmod -R u+w "$work"; rm -rf "$work"' EXIT

# read_pfm(name), for the tests' Python: (width, height, values) of a PFM file, the values one
# flat tuple of floats, three per pixel, rows bottom to top as PFM stores them.
mkdir "$work/.python"
cat >"$work/.python/pfm.py" <<'PY'
import struct
def read_pfm(name):
    data = open(name, "rb").read()
    lines = data.split(b"\n", 3)
    width, height = map(int, lines[1].split())
    order = "<" if float(lines[2]) < 0 else ">"
    return width, height, struct.unpack(f"{order}{width * height * 3}f", lines[3][:width * height * 12])
PY
export PYTHONPATH="$work/.python${PYTHONPATH:+:$PYTHONPATH}"

# check NAME COMMAND...: one check, passed when COMMAND succeeds.
check() {
    local name=$1; shift
    if "$@"; then passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAILED: $name" >&2; fi
}

# expect_exit STATUS MESSAGE-PATTERN -- COMMAND...: COMMAND exits with STATUS and says
# MESSAGE-PATTERN (grep) on stderr, in one line. Its output stays in $work/out and $work/err.
# The batch stage lines ("radiosity: [mesh] ...", printed when stderr is not a terminal, as
# here) come before an error and are not counted.
expect_exit() {
    local want=$1 pattern=$2; shift 3
    "$@" >"$work/out" 2>"$work/err"
    local got=$?
    check "exit $want (got $got) from $*" test "$got" -eq "$want"
    check "message /$pattern/ from $*" grep -q -- "$pattern" "$work/err"
    check "one line on stderr from $*" test "$(grep -vc '^radiosity: \[' "$work/err")" -le 1
}

# write_plane_obj: plane.obj and plane.mtl in the current directory, a 2 x 2 grey (0.5) square
# at y = 0 facing +y, surface 'floor'.
write_plane_obj() {
    printf 'mtllib plane.mtl\nv -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\nusemtl grey\no floor\nf 1 2 3 4\n' > plane.obj
    printf 'newmtl grey\nKd 0.5 0.5 0.5\n' > plane.mtl
}

# finish: the closing line; the test's status.
finish() {
    echo "$passed passed, $failed failed"
    if ((passed + failed == 0)); then echo "FAILED: no check ran" >&2; return 1; fi
    test "$failed" -eq 0
}
