#!/usr/bin/env bash
# cli_loose_ends.sh - what a user tripped over (issues 15 and 16), each held here:
# - a hierarchical solve stopped by --max-memory reports a finite residual (the oracle's largest
#   known error, over the link error) and the largest error known, in the table, --json and
#   --log; it used to report about 1e39-1e42, the sentinel error of links whose ends overlap; a
#   budget too small for the first links is one line naming them, exit 1, nothing written;
# - a hierarchical solve ended by the tail rule (a step that refined at most 0.2% of its links)
#   is converged ("converged (tail rule)", "converged": true, "stop": "tail") with the oracle's
#   error as its residual, at most the link error; it used to read "converged": false with the
#   count of links refined as its residual.
# Usage: cli_loose_ends.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"
cd "$work" || exit 1

# ---- The memory budget stops the hierarchy (issue 15) ------------------------------------------
"$radiosity" scenes --generate office 2000 office.obj >/dev/null 2>&1
check "office generated" test -s office.obj
# Two runs, each checked several ways: --json and --log on 2 threads; the table on 1 thread, whose
# log and numbers must be the 2-thread run's.
"$radiosity" solve office.obj --solver hierarchical --max-memory 2 --json --log budget.csv \
    --threads 2 >budget.json 2>budget.err
check "budget: exit 0, the solution so far" test $? -eq 0
budget_numbers() {
    python3 - budget.json budget.csv <<'PY'
import csv, json, math, sys
j = json.load(open(sys.argv[1]))
rows = list(csv.DictReader(open(sys.argv[2])))
last = rows[-1]
print(f"stop {j['stop']}, residual {j['residual']}, largest error {j['largest_error']}, "
      f"links {j['links']}; log residual {last['residual']}, largest {last['largest_error']}")
ok = j["stop"] == "memory-budget" and not j["converged"]
# The largest error is the oracle's largest known one: finite, far from FLT_MAX's 3.4e38, over
# the threshold; the residual is the same error in the link error's units (1e-3 by default).
ok &= j["largest_error"] is not None and math.isfinite(j["largest_error"]) and 1 < j["largest_error"] < 1e20
ok &= j["residual"] is not None and abs(j["residual"] - 1e-3 * j["largest_error"]) <= 1e-9 * j["residual"]
ok &= abs(float(last["residual"]) - j["residual"]) <= 1e-8 * j["residual"]  # %.9g in the log
ok &= float(last["largest_error"]) < 1e20
sys.exit(0 if ok else 1)
PY
}
check "budget: finite residual and largest error in --json and --log" budget_numbers
check "budget: the step says what is left" grep -Eq 'the memory budget leaves [0-9]+ links over the threshold' budget.err
"$radiosity" solve office.obj --solver hierarchical --max-memory 2 --log budget1.csv --threads 1 \
    >budget.table 2>/dev/null
check "budget: the table names the link count" grep -Eq '^hierarchical: [0-9]+ steps?, not converged: memory budget reached \(--max-memory\) at [0-9]+ links' budget.table
check "budget: the same steps on 1 and 2 threads (the log without its times)" \
    cmp <(cut -d, -f1,3- budget.csv) <(cut -d, -f1,3- budget1.csv)
same_table() { # the 1-thread table holds the 2-thread JSON's links, steps and every surface
    python3 - budget.json budget.table <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
table = open(sys.argv[2]).read().splitlines()
want = [f"{p['name']:<16} {p['area']:12.6g}  " + " ".join(f"{x:12.6f}" for x in p["radiosity"]) +
        "  " + " ".join(f"{x:12.6g}" for x in p["power"]) for p in j["patches"]]
head = (f"hierarchical: {j['iterations']} steps, not converged: memory budget reached "
        f"(--max-memory) at {j['links']} links")
print(f"{len(want)} surfaces, {j['links']} links")
sys.exit(0 if table[0].startswith(head) and table[2:] == want else 1)
PY
}
check "budget: the same report on 1 and 2 threads (the table against --json)" same_table

"$radiosity" scenes --generate office 8000 big.obj >/dev/null 2>&1
expect_exit 1 'with 5 links and [0-9]* nodes needs .* not even the first links fit' -- \
    "$radiosity" solve big.obj --solver hierarchical --max-memory 1 --quiet --log tiny.csv --json
check "budget too small: no log written" test ! -e tiny.csv
check "budget too small: no warning that keeps a solution" bash -c '! grep -q "keeping the solution" "$0"' "$work/err"

# --max-memory with a unit, as users write it (60M used to be refused as not a number).
expect_exit 1 'over the memory budget of 1.0 MiB (--max-memory): not even the first links fit' -- \
    "$radiosity" solve big.obj --solver hierarchical --max-memory 1M --quiet
expect_exit 1 'over the memory budget of 1024.0 MiB' -- \
    "$radiosity" pathtrace cornell --width 16384 --height 16384 --max-memory 1GiB -o huge.pfm --quiet
expect_exit 2 'max-memory wants a number of MiB, or a size such as 512M or 2G, not .60X' -- \
    "$radiosity" solve cornell --max-memory 60X
expect_exit 2 'max-memory wants MiB from 1 to' -- "$radiosity" solve cornell --max-memory 512K
# A number past double's range says so (it used to read "wants a number, not '1e-320'").
expect_exit 2 "tolerance: '1e-320' is out of range" -- "$radiosity" solve cornell --tolerance 1e-320

# ---- The tail rule is convergence, the residual the oracle's error (issue 15) ------------------
"$radiosity" solve cornell --solver hierarchical --json >tail.json 2>tail.err
tail_numbers() {
    python3 - tail.json <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
print(f"stop {j['stop']}, converged {j['converged']}, residual {j['residual']}, "
      f"largest error {j['largest_error']}, links {j['links']}")
# Cornell at the default link error (1e-3) stops after a step that refined 4 links of 2,994:
# every link passed the oracle at the radiosities it was refined with, so the largest error left
# is at most the threshold and the residual (that error as a fraction of the emitted power) at
# most the link error.
ok = j["stop"] == "tail" and j["converged"] is True
ok &= 0 < j["largest_error"] <= 1 and 0 < j["residual"] <= 1e-3
ok &= abs(j["residual"] - 1e-3 * j["largest_error"]) <= 1e-9
sys.exit(0 if ok else 1)
PY
}
check "tail rule: converged, the residual the oracle's error at most the link error" tail_numbers
check "tail rule: the stage line says so" grep -Eq '^radiosity: \[solve\] hierarchical, [0-9]+ steps?, residual 0\.00(0[1-9]|1)[0-9]*, converged \(tail rule\)' tail.err
"$radiosity" solve cornell --solver hierarchical >tail.table 2>/dev/null
check "tail rule: the table says what it did" grep -Eq '^hierarchical: [0-9]+ steps?, converged \(tail rule\): the last step refined at most 0.2% of its [0-9]+ links' tail.table
# A solve that refines nothing in its last step is converged (two squares at 1e-4), its residual
# the oracle's largest error, at most the link error.
"$radiosity" solve two-squares --solver hierarchical --link-error 1e-4 --json >conv.json 2>/dev/null
converged_numbers() {
    python3 - conv.json <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
print(f"stop {j['stop']}, converged {j['converged']}, residual {j['residual']}")
sys.exit(0 if j["stop"] == "converged" and j["converged"] is True and 0 <= j["residual"] <= 1e-4 else 1)
PY
}
check "a step that refines nothing: converged, the residual at most the link error" converged_numbers
# Stopped by the time budget in its first step: not converged, the residual not measured.
"$radiosity" scenes --generate office 8000 office8k.obj >/dev/null 2>&1
"$radiosity" solve office8k.obj --solver hierarchical --time-budget 0.05 --json >short.json 2>/dev/null
check "time budget: not converged" grep -q '"converged": false, "residual": null, "stop": "time-budget"' short.json

# ---- A camera that sees only backs draws them (black), with a warning (issue 16) ---------------
# Behind the Cornell box's back wall, looking in: every ray meets the wall's back. The renderer,
# the path tracer and the photon mapper used to refuse this camera; a back of a one-sided surface
# absorbs and is drawn black, as the path tracer always drew backs among fronts.
pixel_sum() { # FILE.pfm: the sum of its values
    python3 - "$1" <<'PY'
import sys
from pfm import read_pfm
print(sum(read_pfm(sys.argv[1])[2]))
PY
}
behind=(cornell --eye 278,273,1200 --look 278,273,0 --width 16 --height 16)
quick=(--elements 100 --tolerance 1e-3 --final-gather 0 --spp 1) # the picture, not the light
"$radiosity" render "${behind[@]}" "${quick[@]}" -o behind_render.pfm 2>behind.err
check "backs only: render draws, exit 0" test $? -eq 0
check "backs only: the render is black" test "$(pixel_sum behind_render.pfm)" = 0.0
check "backs only: one warning naming the wall" test "$(grep -v '^radiosity: \[' behind.err | grep -c "warning: the camera sees only the backs of surfaces (such as 'back-wall'), which are one-sided and drawn black")" -eq 1
check "backs only: nothing else said" test "$(grep -vc '^radiosity: \[' behind.err)" -eq 1
"$radiosity" pathtrace "${behind[@]}" --spp 1 -o behind_pt.pfm --quiet 2>/dev/null
check "backs only: pathtrace draws it black too" test "$(pixel_sum behind_pt.pfm)" = 0.0
# Looking out of the open box at a sky: the sky is what the camera sees (it used to be refused
# as "sees nothing"); without a sky, nothing at all is still refused.
away=(cornell --eye 278,273,-800 --look 278,273,-1600 --width 16 --height 16)
"$radiosity" render "${away[@]}" --sky 1 "${quick[@]}" -o sky.pfm --quiet
check "sky only: render draws it" test $? -eq 0
check "sky only: not black" python3 -c 'import sys; sys.exit(0 if float(sys.argv[1]) > 0 else 1)' "$(pixel_sum sky.pfm)"
"$radiosity" pathtrace "${away[@]}" --sky 1 --spp 1 -o sky_pt.pfm --quiet
check "sky only: pathtrace draws it" test $? -eq 0
expect_exit 1 'camera sees nothing' -- "$radiosity" render "${away[@]}" -o nothing.pfm --quiet
check "nothing seen: no file" test ! -e nothing.pfm

finish
