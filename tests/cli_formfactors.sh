#!/usr/bin/env bash
# cli_formfactors.sh - `radiosity formfactors`: the surface-to-surface matrix as a table and as
# JSON (shape, closed-form values, rows of a closed cube summing to one), every method by name,
# patch systems, and bad input (one line on stderr, exit 1 or 2).
# Usage: cli_formfactors.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"

# near ACTUAL EXPECTED RELATIVE: |actual - expected| <= relative * |expected|
near() { awk -v a="$1" -v e="$2" -v r="$3" 'BEGIN { d = a - e; if (d < 0) d = -d; exit !(d <= r * (e < 0 ? -e : e)) }'; }

"$radiosity" formfactors --help | grep -q -- '--hemicube-res'; check "help" test $? -eq 0

# JSON: the issue's shape, and the opposed unit squares' closed form within 1% by every method.
for method in analytic hemicube raycast montecarlo; do
    "$radiosity" formfactors two-squares --ff "$method" --elements 400 --json --quiet >"$work/$method.json"
    check "$method exit" test $? -eq 0
    check "$method surfaces" grep -q '^{"surfaces": \[' "$work/$method.json"
    check "$method names" grep -q '{"name": "emitter", "area": ' "$work/$method.json"
    check "$method matrix" grep -q '"form_factors": \[' "$work/$method.json"
    # Rows follow "form_factors": the first is [F_00, F_01].
    f01=$(sed -n '/"form_factors"/,$p' "$work/$method.json" | grep -o '\[0, [0-9.e-]*\]' | head -1 | tr -d '[]' | cut -d, -f2)
    check "$method F = 0.1998 (got ${f01:-nothing})" near "${f01:-0}" 0.199824895698 0.01
done
if command -v python3 >/dev/null; then
    python3 - "$work/analytic.json" <<'PY'
import json, sys
data = json.load(open(sys.argv[1]))
assert set(data) == {"surfaces", "form_factors"}, data.keys()
assert [s["name"] for s in data["surfaces"]] == ["emitter", "receiver"]
assert abs(data["surfaces"][0]["area"] - 1) < 1e-9
assert len(data["form_factors"]) == 2 and all(len(r) == 2 for r in data["form_factors"])
PY
    check "JSON parses with the issue's keys" test $? -eq 0
fi

# A closed cube: every row of the table sums to one (last column).
"$radiosity" formfactors unit-cube --elements 600 --quiet >"$work/cube.txt"
check "cube exit" test $? -eq 0
check "cube header" grep -q '^form factors (analytic): 6 surfaces' "$work/cube.txt"
sums=$(awk '$1 ~ /^(bottom|top|front|back|left|right)$/ { print $NF }' "$work/cube.txt")
check "six rows" test "$(echo "$sums" | wc -l)" -eq 6
for s in $sums; do check "row sum $s" near "$s" 1 0.002; done

# Options reach the methods.
"$radiosity" formfactors two-squares --ff hemicube --hemicube-res 32 --elements 100 --quiet >"$work/h.txt"
check "hemicube resolution" test $? -eq 0
"$radiosity" formfactors two-squares --ff raycast --ff-samples 2 --patch-size 0.5 --element-size 0.25 \
    --quiet >"$work/r.txt"
check "samples and sizes" grep -q ', 8 patches, 32 elements' "$work/r.txt"
# Same seed, same numbers, whatever the thread count.
"$radiosity" formfactors cornell --ff montecarlo --elements 300 --json --threads 1 --quiet >"$work/t1.json"
"$radiosity" formfactors cornell --ff montecarlo --elements 300 --json --threads 2 --quiet >"$work/t2.json"
check "thread count does not change results" cmp -s "$work/t1.json" "$work/t2.json"

# A patch system: its given factors come back.
"$radiosity" formfactors "$source_dir/scenes/four-walls.ffm" --quiet >"$work/ffm.txt"
check "patch system" grep -q '^form factors (given)' "$work/ffm.txt"

# Bad input.
expect_exit 2 'unknown form-factor method' -- "$radiosity" formfactors cornell --ff radiant
expect_exit 2 'which scene' -- "$radiosity" formfactors
expect_exit 2 'whole number' -- "$radiosity" formfactors cornell --ff-samples -3
expect_exit 1 'no-such-file.obj' -- "$radiosity" formfactors "$work/no-such-file.obj"
expect_exit 1 'resolution' -- "$radiosity" formfactors cornell --ff hemicube --hemicube-res 100000

# The surface table (8 n^2 bytes) is held to --max-memory: 400 separate quads need 1.2 MiB.
printf 'newmtl light\nKd 0.5 0.5 0.5\nKe 1 1 1\n' >"$work/quads.mtl"
awk 'BEGIN { print "mtllib quads.mtl\nusemtl light"; for (i = 0; i < 400; ++i) {
    x = (i % 20) * 2; z = int(i / 20) * 2; k = 4 * i
    printf "o s%d\nv %d 0 %d\nv %d 0 %d\nv %d 0 %d\nv %d 0 %d\nf %d %d %d %d\n", i,
        x, z, x + 1, z, x + 1, z + 1, x, z + 1, k + 1, k + 4, k + 3, k + 2 } }' >"$work/quads.obj"
expect_exit 1 'the form-factor table of 400 surfaces needs 1.2 MiB, over the memory budget of 1.0 MiB (--max-memory)' \
    -- "$radiosity" formfactors "$work/quads.obj" --elements 400 --max-memory 1 --quiet
"$radiosity" formfactors "$work/quads.obj" --elements 400 --max-memory 2 --quiet >"$work/quads.txt"
check "the table within the budget" grep -q '^form factors (analytic): 400 surfaces' "$work/quads.txt"

finish
