#!/usr/bin/env python3
"""Compares two linear images (.pfm) in square blocks, the way issue 16 measures images: the
relative error of each block's mean (RGB mean) against a far-converged reference.

usage: block_compare.py TEST.pfm REF.pfm [--blocks 4,8,16] [--emitter Y] [--worst N]

For each block size: the relative RMSE over the blocks, the worst block (with its top-left
corner, counted from the top left of the image) and how many blocks are off by more than 4%;
then the N worst blocks of the second size given (8 by default). Blocks holding a reference pixel
brighter than Y (default 2.0: the Cornell light, whose radiance is far above any lit wall's) are
left out; `--emitter inf` keeps every block. Blocks whose reference is black are left out too.
After each size's line, one more gives the RMSE without the blocks whose reference mean is below
1% of the image's mean (the box's edges against the black outside: a sliver of a wall in one
pixel column, whose relative error is large for a tiny absolute one); the plain number stays the
one the targets are stated in.
Pure Python (no numpy): small images only."""
import math
import struct
import sys


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        if kind not in (b"PF", b"Pf"):
            sys.exit(f"{path}: not a PFM")
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        channels = 3 if kind == b"PF" else 1
        data = f.read()
    endian = "<" if scale < 0 else ">"
    count = width * height * channels
    values = struct.unpack("%s%df" % (endian, count), data[:4 * count])
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
            if bright or r <= 1e-6 * size * size:
                continue
            out.append(((t - r) / r, bx, height - by - size, r / (size * size)))
    return out


def option(args, name, default):
    return args[args.index(name) + 1] if name in args else default


def main():
    args = sys.argv[1:]
    if len(args) < 2:
        sys.exit(__doc__)
    emitter = float(option(args, "--emitter", "2.0"))
    worst = int(option(args, "--worst", "5"))
    sizes = [int(b) for b in option(args, "--blocks", "4,8,16").split(",")]
    wt, ht, test = read_pfm(args[0])
    wr, hr, ref = read_pfm(args[1])
    if (wt, ht) != (wr, hr):
        sys.exit("the images differ in size")
    mean_t, mean_r = sum(test) / len(test), sum(ref) / len(ref)
    print(f"mean {mean_t:.6g} vs {mean_r:.6g} ({100 * (mean_t / mean_r - 1):+.3f}%)")
    listed = None
    for size in sizes:
        found = blocks(wt, ht, test, ref, size, emitter)
        if not found:
            print(f"{size}x{size} blocks: none to compare")
            continue
        found.sort(key=lambda b: -abs(b[0]))
        rmse = math.sqrt(sum(b[0] * b[0] for b in found) / len(found))
        e, x, y, _ = found[0]
        over = sum(1 for b in found if abs(b[0]) > 0.04)
        print(f"{size}x{size} blocks: relative RMSE {100 * rmse:.2f}%, worst {100 * e:+.1f}% "
              f"at x {x} y {y}, {over} of {len(found)} off by more than 4%")
        lit = [b for b in found if b[3] >= 0.01 * mean_r]
        if lit and len(lit) < len(found):
            rmse = math.sqrt(sum(b[0] * b[0] for b in lit) / len(lit))
            e, x, y, _ = lit[0]
            print(f"  without the {len(found) - len(lit)} blocks under 1% of the mean: relative "
                  f"RMSE {100 * rmse:.2f}%, worst {100 * e:+.1f}% at x {x} y {y}")
        if listed is None or size == sizes[min(1, len(sizes) - 1)]:
            listed = (size, found)
    if listed:
        size, found = listed
        for e, x, y, _ in found[:worst]:
            print(f"  {size}x{size} block at x {x:3d} y {y:3d}: {100 * e:+.1f}%")


if __name__ == "__main__":
    main()
