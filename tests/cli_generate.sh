#!/usr/bin/env bash
# cli_generate.sh - `radiosity scenes --generate office TRIANGLES FILE.obj`: about the asked
# number of triangles, the same file every time, lit (the lamps emit), and bad arguments refused.
# Usage: cli_generate.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"

"$radiosity" scenes --generate office 3000 "$work/a.obj"
check "written" test -s "$work/a.obj" -a -s "$work/a.mtl"
triangles=$(awk '/^f /{t += NF - 3} END {print t}' "$work/a.obj")
check "about 3000 triangles ($triangles)" test "$triangles" -ge 2400 -a "$triangles" -le 3600
"$radiosity" scenes --generate office 3000 "$work/b.obj"
check "deterministic" cmp <(grep -v '^mtllib' "$work/a.obj") <(grep -v '^mtllib' "$work/b.obj")
check "lamps emit" grep -q '^Ke [1-9]' "$work/a.mtl"
"$radiosity" scenes --generate office 30000 "$work/c.obj"
triangles=$(awk '/^f /{t += NF - 3} END {print t}' "$work/c.obj")
check "about 30000 triangles ($triangles)" test "$triangles" -ge 27000 -a "$triangles" -le 33000
check "partition walls at 30000" test "$(grep -c '^f ' "$work/c.obj")" -gt 10000
"$radiosity" solve "$work/a.obj" --solver hierarchical --quiet >"$work/table"
check "solves" grep -Eq '^floor +[0-9.]+ +[0-9]*\.[0-9]*[1-9]' "$work/table"

expect_exit 2 'triangle count' -- "$radiosity" scenes --generate office 10 "$work/x.obj"
expect_exit 2 'triangle count' -- "$radiosity" scenes --generate office many "$work/x.obj"
expect_exit 2 'unknown generator' -- "$radiosity" scenes --generate castle 1000 "$work/x.obj"
expect_exit 2 'needs a triangle count' -- "$radiosity" scenes --generate office "$work/x.obj"
check "nothing written" test ! -e "$work/x.obj"
finish
