#!/bin/sh
# make_sponza_atrium.sh - the sky-lit atrium of docs/lights.md: a copy of the shared Sponza
# (../shared/scenes/sponza/sponza_lit.obj) without its emitting `sky` quad, so that light enters
# only through the open roof from --sky (and --sun).
# Usage: scripts/make_sponza_atrium.sh [SPONZA_DIR [OUT_DIR]]   (default ../shared/scenes/sponza,
# build/sponza_atrium); writes OUT_DIR/sponza_atrium.obj and its .mtl.
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
source_dir=${1:-$here/../shared/scenes/sponza}
out_dir=${2:-$here/build/sponza_atrium}
mkdir -p "$out_dir"
# Every line up to the `o sky` object (the last one in the file); the MTL under the new name.
awk '/^o sky$/ { exit } { print }' "$source_dir/sponza_lit.obj" |
    sed 's/^mtllib sponza_lit.mtl$/mtllib sponza_atrium.mtl/' > "$out_dir/sponza_atrium.obj"
cp "$source_dir/sponza_lit.mtl" "$out_dir/sponza_atrium.mtl"
chmod u+w "$out_dir/sponza_atrium.mtl"
if grep -q '^o sky$' "$out_dir/sponza_atrium.obj"; then
    echo "make_sponza_atrium.sh: the sky quad is still there" >&2
    exit 1
fi
echo "$out_dir/sponza_atrium.obj"
