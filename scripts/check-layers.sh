#!/usr/bin/env bash
# check-layers.sh [SOURCE_DIR] - draws the include graph of the folders of src/ (which folder
# includes headers of which) and fails when it has a cycle: folders must only point down
# (docs/architecture.md). Also fails when a file of cli/ includes anything of src/ (the tool
# uses only the public header).
# Prints one line per folder, "folder -> the folders it includes", then the layers from the
# bottom, and "layers: ok" or "layers: cycle among ...".
set -u
root=${1:-$(dirname "$0")/..}
cd "$root" || exit 2
[ -d src ] || { echo "check-layers: no src/ in $root" >&2; exit 2; }

# Edges "from to", one per line, for #include "to/..." in src/from/.
edges=$(for dir in src/*/; do
    from=$(basename "$dir")
    grep -ho '^[[:space:]]*#[[:space:]]*include[[:space:]]*"[A-Za-z0-9_]*/' "$dir"* 2>/dev/null |
        sed 's/.*"//; s/\/$//' | sort -u | while read -r to; do
            [ "$to" != "$from" ] && [ -d "src/$to" ] && echo "$from $to"
        done
done)
folders=$(for dir in src/*/; do basename "$dir"; done)

status=0
for f in $folders; do
    echo "$f -> $(echo "$edges" | awk -v f="$f" '$1 == f { printf "%s ", $2 }')"
done

# Peel off folders that include nothing left, layer by layer; what cannot be peeled is a cycle.
echo "$edges" | awk -v folders="$folders" '
    BEGIN { n = split(folders, all, /[ \n]+/); for (i = 1; i <= n; ++i) if (all[i] != "") left[all[i]] = 1 }
    NF == 2 { out[$1, $2] = 1 }
    END {
        layer = 0
        while (1) {
            line = ""
            for (f in left) {
                ready = 1
                for (g in left) if (g != f && ((f, g) in out)) ready = 0
                if (ready) { line = line " " f; peel[f] = 1 }
            }
            if (line == "") break
            for (f in peel) delete left[f]
            delete peel
            printf "layer %d:%s\n", layer++, line
        }
        # Folders that only include a cycle (nothing left includes them) are not in it.
        do {
            changed = 0
            for (f in left) {
                used = 0
                for (g in left) if (g != f && ((g, f) in out)) used = 1
                if (!used) { delete left[f]; changed = 1 }
            }
        } while (changed)
        rest = ""
        for (f in left) rest = rest " " f
        if (rest != "") { printf "layers: cycle among%s\n", rest; exit 1 }
        print "layers: ok"
    }' || status=1

if [ -d cli ]; then
    bad=$(for f in cli/*.[ch]; do
        [ -f "$f" ] || continue
        grep -ho '^[[:space:]]*#[[:space:]]*include[[:space:]]*"[A-Za-z0-9_]*/' "$f" |
            sed 's/.*"//; s/\/$//' | while read -r to; do [ -d "src/$to" ] && echo "$f"; done
    done | sort -u | tr '\n' ' ')
    if [ -n "$bad" ]; then echo "layers: cli/ includes library internals: $bad"; status=1; fi
fi
exit $status
