#!/usr/bin/env python3
"""Noise or bias: compares renders of one scene at several seeds with a far-converged reference
in square blocks, the way block_compare.py compares one.

usage: seed_blocks.py REF.pfm S0.pfm S1.pfm ... [--blocks 8,16] [--emitter Y] [--worst N]

For each block size: the relative RMSE of the seeds' mean image (the bias, plus the noise left
after averaging: about the spread over the square root of the seed count), the blocks' standard
deviation over the seeds (rms over the blocks: the noise), and the N blocks whose worst seed is
furthest off, each with its mean over the seeds, its standard deviation and its range. Then the
image mean of each seed. A block whose mean over the seeds is well inside its range is noise; one
off at every seed is bias. Blocks are counted from the top left, as block_compare.py counts them.
Pure Python (no numpy): small images only."""
import math
import sys

from block_compare import blocks, option, read_pfm


def main():
    args = sys.argv[1:]
    files = [a for i, a in enumerate(args)
             if not a.startswith("--") and (i == 0 or not args[i - 1].startswith("--"))]
    if len(files) < 3:
        sys.exit(__doc__)
    width, height, ref = read_pfm(files[0])
    seeds = [read_pfm(f) for f in files[1:]]
    if any((w, h) != (width, height) for w, h, _ in seeds):
        sys.exit("the images differ in size")
    # The options as block_compare.py reads them (its defaults, but 8x8 and 16x16 blocks).
    sizes = [int(b) for b in option(args, "--blocks", "8,16").split(",")]
    emitter, worst = float(option(args, "--emitter", "2.0")), int(option(args, "--worst", "5"))
    n = len(seeds)
    for size in sizes:
        # Per seed, per block: (relative error, x, y, reference mean); the same blocks each time.
        per_seed = [blocks(width, height, image, ref, size, emitter) for _, _, image in seeds]
        if not per_seed[0]:
            print(f"{size}x{size} blocks: none to compare")
            continue
        rows = []
        for k, (_, x, y, _) in enumerate(per_seed[0]):
            errors = [found[k][0] for found in per_seed]
            mean = sum(errors) / n
            spread = math.sqrt(sum((e - mean) ** 2 for e in errors) / (n - 1))
            rows.append((mean, spread, min(errors), max(errors), x, y))
        bias = math.sqrt(sum(r[0] ** 2 for r in rows) / len(rows))
        noise = math.sqrt(sum(r[1] ** 2 for r in rows) / len(rows))
        print(f"{size}x{size} blocks over {n} seeds: the mean image's relative RMSE {100 * bias:.2f}%, "
              f"the blocks' standard deviation {100 * noise:.2f}% (rms over {len(rows)} blocks)")
        rows.sort(key=lambda r: -max(abs(r[2]), abs(r[3])))
        for mean, spread, low, high, x, y in rows[:worst]:
            print(f"  x {x:3d} y {y:3d}: mean {100 * mean:+.2f}%, standard deviation "
                  f"{100 * spread:.2f}%, seeds {100 * low:+.1f} to {100 * high:+.1f}%")
    total = sum(ref)
    print("image means: " + " ".join(f"{100 * (sum(image) / total - 1):+.2f}%" for _, _, image in seeds))


if __name__ == "__main__":
    main()
