#!/usr/bin/env python3
"""block_error.py - relative error of an image against a far-converged reference, in blocks.

    bench/block_error.py TEST.pfm REFERENCE.pfm [BLOCK ...]     (default blocks: 4 8 16)

For each block size b the images are averaged over b x b pixel blocks (the mean of the three
channels); a block's relative error is (test - ref) / ref; printed are the RMSE of that over
the blocks whose reference is not black and the worst block. Pure Python (no numpy): small
images only. The issue 16 measure is the 4x4-block relative RMSE."""
import math
import struct
import sys


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        if kind != b"PF":
            sys.exit(f"{path}: not a colour PFM")
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        endian = "<" if scale < 0 else ">"
        data = struct.unpack(endian + "f" * (3 * width * height), f.read(12 * width * height))
    grey = [(data[3 * i] + data[3 * i + 1] + data[3 * i + 2]) / 3 for i in range(width * height)]
    return width, height, grey


def block_means(width, height, grey, b):
    out = []
    for by in range(height // b):
        for bx in range(width // b):
            s = 0.0
            for y in range(by * b, by * b + b):
                row = y * width
                s += sum(grey[row + bx * b: row + bx * b + b])
            out.append(s / (b * b))
    return out


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    wt, ht, test = read_pfm(sys.argv[1])
    wr, hr, ref = read_pfm(sys.argv[2])
    if (wt, ht) != (wr, hr):
        sys.exit("the images differ in size")
    blocks = [int(b) for b in sys.argv[3:]] or [4, 8, 16]
    mean_t, mean_r = sum(test) / len(test), sum(ref) / len(ref)
    print(f"mean {mean_t:.6g} vs {mean_r:.6g} ({100 * (mean_t / mean_r - 1):+.3f}%)")
    for b in blocks:
        t, r = block_means(wt, ht, test, b), block_means(wr, hr, ref, b)
        errors = [(x - y) / y for x, y in zip(t, r) if y > 1e-6]
        rmse = math.sqrt(sum(e * e for e in errors) / len(errors))
        worst = max(abs(e) for e in errors)
        print(f"{b}x{b} blocks: relative RMSE {100 * rmse:.3f}%, worst {100 * worst:.3f}%")


main()
