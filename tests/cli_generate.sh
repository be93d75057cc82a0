#!/usr/bin/env bash
# cli_generate.sh - `radiosity scenes --generate office TRIANGLES FILE.obj`: about the asked
# (and `--generate house FILE.obj`: deterministic, lit, its energy balance in `solve --json`)
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

# The house: written the same every time, one lamp, and its energy balance in solve --json.
"$radiosity" scenes --generate house "$work/h.obj"
"$radiosity" scenes --generate house "$work/h2.obj"
check "house written" test -s "$work/h.obj" -a -s "$work/h.mtl"
check "house deterministic" cmp <(grep -v '^mtllib' "$work/h.obj") <(grep -v '^mtllib' "$work/h2.obj")
check "house lamp emits" grep -q '^Ke [1-9]' "$work/h.mtl"
"$radiosity" solve "$work/h.obj" --elements 300 --tolerance 1e-2 --json --quiet >"$work/h.json"
check "energy balance in the JSON" grep -Eq '"energy": \{"emitted": \[[0-9.]+, .*"escaped_fraction": ' "$work/h.json"
expect_exit 2 'needs an output file' -- "$radiosity" scenes --generate house
expect_exit 2 'triangle count' -- "$radiosity" scenes --generate office 10 "$work/x.obj"
expect_exit 2 'triangle count' -- "$radiosity" scenes --generate office many "$work/x.obj"
expect_exit 2 'unknown generator' -- "$radiosity" scenes --generate castle 1000 "$work/x.obj"
expect_exit 2 'needs a triangle count' -- "$radiosity" scenes --generate office "$work/x.obj"
check "nothing written" test ! -e "$work/x.obj"
finish
