#!/usr/bin/env python3
"""Compares two linear images (.pfm) in square blocks, the way issue 16 measures the contact
bands: the relative error of each block's mean (RGB mean) against the reference.

usage: block_compare.py TEST.pfm REF.pfm [--emitter Y] [--worst N]

Prints the block relative RMSE at 4x4, the worst 8x8 block and how many 8x8 blocks are off by
more than 4%. Blocks holding a reference pixel brighter than Y (default 2.0: the light, whose
radiance is far above any lit wall's) are left out."""
import math
import struct
import sys


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        channels = 3 if kind == b"PF" else 1
        data = f.read()
    endian = "<" if scale < 0 else ">"
    values = struct.unpack("%s%df" % (endian, width * height * channels), data[:4 * width * height * channels])
    grey = [sum(values[i * channels:(i + 1) * channels]) / channels for i in range(width * height)]
    return width, height, grey  # rows bottom to top, as stored


def blocks(width, height, test, ref, size, emitter):
    out = []
    for by in range(0, height - size + 1, size):
        for bx in range(0, width - size + 1, size):
            t = r = 0.0
            bright = False
            for y in range(by, by + size):
                for x in range(bx, bx + size):
                    t += test[y * width + x]
                    r += ref[y * width + x]
                    bright |= ref[y * width + x] > emitter
            if bright or r <= 0:
                continue
            out.append(((t - r) / r, bx, height - by - size))  # top-left corner, from the top
    return out


def main():
    args = sys.argv[1:]
    if len(args) < 2:
        sys.exit(__doc__)
    emitter = float(args[args.index("--emitter") + 1]) if "--emitter" in args else 2.0
    worst = int(args[args.index("--worst") + 1]) if "--worst" in args else 5
    wt, ht, test = read_pfm(args[0])
    wr, hr, ref = read_pfm(args[1])
    if (wt, ht) != (wr, hr):
        sys.exit("sizes differ")
    b4 = blocks(wt, ht, test, ref, 4, emitter)
    rmse = math.sqrt(sum(e * e for e, _, _ in b4) / len(b4))
    b8 = blocks(wt, ht, test, ref, 8, emitter)
    b8.sort(key=lambda b: -abs(b[0]))
    mean_t = sum(test) / len(test)
    mean_r = sum(ref) / len(ref)
    print("mean %+.2f%%  4x4 block rel RMSE %.2f%%  8x8 worst %+.1f%%  8x8 over 4%%: %d of %d"
          % (100 * (mean_t / mean_r - 1), 100 * rmse, 100 * b8[0][0],
             sum(1 for b in b8 if abs(b[0]) > 0.04), len(b8)))
    for e, x, y in b8[:worst]:
        print("  8x8 block at x %3d y %3d (from the top left): %+.1f%%" % (x, y, 100 * e))


if __name__ == "__main__":
    main()
