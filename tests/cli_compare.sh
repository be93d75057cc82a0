#!/usr/bin/env bash
# cli_compare.sh - `radiosity compare`: metrics on hand-made PFM images with known answers,
# JSON, the --diff map, .hdr input, and bad input (one line, exit 1 or 2, no file left).
# Usage: cli_compare.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"

# pfm FILE WIDTH HEIGHT VALUE: a little-endian PFM filled with one value.
pfm() {
    python3 - "$@" <<'PY'
import struct, sys
path, w, h, v = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
with open(path, "wb") as f:
    f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
    f.write(struct.pack("<%df" % (w * h * 3), *([v] * (w * h * 3))))
PY
}

pfm "$work/one.pfm" 8 4 1.0
pfm "$work/more.pfm" 8 4 1.1
pfm "$work/tall.pfm" 4 8 1.0

"$radiosity" compare "$work/more.pfm" "$work/one.pfm" >"$work/out"
check "exit 0" test $? -eq 0
check "rmse" grep -Eq '^rmse +0\.1$' "$work/out"
check "relative mse" grep -Eq '^relative mse +0\.00990099' "$work/out"
check "psnr" grep -Eq '^psnr +20 dB \(peak 1\)$' "$work/out"
check "mean ratio" grep -Eq '= 1\.1$' "$work/out"

"$radiosity" compare "$work/more.pfm" "$work/one.pfm" --json >"$work/out"
check "json" grep -Eq '^\{"width": 8, "height": 4, "rmse": 0\.1000000[0-9]*, "relative_mse": 0\.0099' "$work/out"
"$radiosity" compare "$work/one.pfm" "$work/one.pfm" --json >"$work/out"
check "json identical: psnr null" grep -q '"rmse": 0, "relative_mse": 0, "psnr": null' "$work/out"

"$radiosity" compare "$work/more.pfm" "$work/one.pfm" --diff "$work/diff.png" >"$work/out"
check "diff written" test -s "$work/diff.png"
check "diff reported" grep -q 'diff.png' "$work/out"

# A path-traced .hdr against itself as .pfm: the RGBE rounding only.
"$radiosity" pathtrace -o "$work/a.pfm" --width 16 --height 16 --spp 1 --quiet
"$radiosity" pathtrace -o "$work/a.hdr" --width 16 --height 16 --spp 1 --quiet
"$radiosity" compare "$work/a.hdr" "$work/a.pfm" --json >"$work/out"
check "hdr reads" grep -q '"mean_ratio": 0\.99' "$work/out"

# EXR (OpenEXR): 32-bit float is the PFM bit for bit; --half rounds to 11 bits; render writes it.
"$radiosity" pathtrace -o "$work/a.exr" --width 16 --height 16 --spp 1 --quiet
"$radiosity" compare "$work/a.exr" "$work/a.pfm" >"$work/out"
check "exr float equals pfm" grep -Eq '^rmse +0$' "$work/out"
"$radiosity" pathtrace -o "$work/h.exr" --half --width 16 --height 16 --spp 1 --quiet
"$radiosity" compare "$work/h.exr" "$work/a.pfm" --json >"$work/out"
check "exr half close" grep -Eq '"mean_ratio": (0\.999[0-9]*|1\.000[0-9]*|1)[,}]' "$work/out"
check "exr half is smaller" test "$(stat -c %s "$work/h.exr")" -lt "$(stat -c %s "$work/a.exr")"
"$radiosity" render -o "$work/r.exr" --width 16 --height 16 --elements 40 --quiet
check "render writes exr" test -s "$work/r.exr"
head -c 200 "$work/a.exr" >"$work/cut.exr"
expect_exit 1 'cut.exr: not a readable EXR file' -- "$radiosity" compare "$work/cut.exr" "$work/a.pfm"
head -c 100 /dev/urandom >"$work/garbage.exr"
expect_exit 1 'garbage.exr: not a readable EXR file' -- "$radiosity" compare "$work/a.pfm" "$work/garbage.exr"
rm -f "$work/a.exr" "$work/h.exr" "$work/r.exr" "$work/cut.exr" "$work/garbage.exr"

rm -f "$work/diff.png" "$work/a.hdr" "$work/a.pfm"
expect_exit 2 'needs two images' -- "$radiosity" compare "$work/one.pfm"
expect_exit 2 'unknown option' -- "$radiosity" compare "$work/one.pfm" "$work/one.pfm" --frobnicate
expect_exit 2 'unknown image format' -- "$radiosity" compare "$work/one.pfm" "$work/one.pfm" --diff "$work/d.gif"
expect_exit 1 'differ in size: 8x4 against a 4x8' -- "$radiosity" compare "$work/one.pfm" "$work/tall.pfm" --diff "$work/d.png"
expect_exit 1 'missing.pfm: cannot open' -- "$radiosity" compare "$work/missing.pfm" "$work/one.pfm"
expect_exit 1 'only read linear images' -- "$radiosity" compare "$work/one.png" "$work/one.pfm"
head -c 100 /dev/urandom >"$work/garbage.pfm"
expect_exit 1 'garbage.pfm: not a PFM file' -- "$radiosity" compare "$work/garbage.pfm" "$work/one.pfm"
check "no diff left behind" test -z "$(ls "$work" | grep -v -e '\.pfm$' -e '^out$' -e '^err$')"

finish
