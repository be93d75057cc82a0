#!/usr/bin/env bash
# stress-room.sh - the default solve of scenes/room.obj N times in a row (default 200): no abort,
# no signal, the same answer every time. It stands guard over the Embree packet lanes (issue 13:
# unfilled lanes made Debian's Embree abort on about half of these runs on some processors).
# Usage: scripts/stress-room.sh [N] [RADIOSITY]          (not in CI: minutes of work)
set -uo pipefail
cd "$(dirname "$0")/.."
runs=${1:-200}
radiosity=${2:-build/radiosity}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failed=0
"$radiosity" solve scenes/room.obj --quiet >"$work/first" 2>/dev/null || failed=1
for ((i = 2; i <= runs && failed == 0; ++i)); do
    "$radiosity" solve scenes/room.obj --quiet >"$work/out" 2>"$work/err"
    status=$?
    if ((status != 0)); then
        echo "stress-room: run $i exited with $status: $(tail -n 1 "$work/err")" >&2
        failed=1
    elif ! cmp -s "$work/first" "$work/out"; then
        echo "stress-room: run $i gave another answer" >&2
        failed=1
    fi
done
((failed == 0)) && echo "stress-room: $runs runs, no failure, identical output"
exit "$failed"
