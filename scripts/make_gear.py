#!/usr/bin/env python3
"""Writes an OBJ of a gear-shaped floor (one non-convex face) lit by a quad lamp above it, for
the importer's cut of non-convex faces of many corners (issue 16, docs/meshing.md).

usage: make_gear.py OUT.obj [TEETH=10000] [ROOT=0.8] [TIP=1] [LAMP_HEIGHT=1] [--comb]

The gear has 4 corners per tooth (two on the root circle, two on the tip circle), so TEETH
teeth give a face of 4 TEETH corners, counter-clockwise seen from above (z = 0, facing +z).
Each tooth spans half of its angular pitch at the root and a quarter at the tip. The lamp is a
square of side 0.5 at z = LAMP_HEIGHT facing down (material "light", radiance 1). With --comb
the face is a comb instead: a bar along x with TEETH teeth of height 1 standing on it."""
import math
import os
import sys


def gear(teeth, root, tip):
    points = []
    pitch = 2 * math.pi / teeth
    for k in range(teeth):
        a = k * pitch
        for angle, radius in ((a, root), (a + 0.125 * pitch, tip), (a + 0.375 * pitch, tip),
                              (a + 0.5 * pitch, root)):
            points.append((radius * math.cos(angle), radius * math.sin(angle)))
    return points


def comb(teeth):
    # Bar 0..2 in x, 0..0.2 in y; teeth of width 1/(2 TEETH) * 2 and height 1 above it.
    width = 2.0 / teeth
    points = [(0.0, 0.0), (2.0, 0.0)]
    for k in reversed(range(teeth)):
        x0 = k * width
        points += [(x0 + 0.75 * width, 0.2), (x0 + 0.75 * width, 1.2), (x0 + 0.25 * width, 1.2),
                   (x0 + 0.25 * width, 0.2)]
    return [(x - 1.0, y - 0.6) for x, y in points]


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if not args:
        sys.exit(__doc__)
    out = args[0]
    teeth = int(args[1]) if len(args) > 1 else 10000
    root = float(args[2]) if len(args) > 2 else 0.8
    tip = float(args[3]) if len(args) > 3 else 1.0
    height = float(args[4]) if len(args) > 4 else 1.0
    points = comb(teeth) if "--comb" in sys.argv else gear(teeth, root, tip)
    mtl = os.path.splitext(out)[0] + ".mtl"
    with open(mtl, "w") as f:
        f.write("newmtl light\nKd 0 0 0\nKe 1 1 1\nnewmtl grey\nKd 0.5 0.5 0.5\n")
    with open(out, "w") as f:
        f.write("mtllib %s\n" % os.path.basename(mtl))
        for x, y in points:
            f.write("v %.9g %.9g 0\n" % (x, y))
        s = 0.25
        for x, y in ((-s, -s), (-s, s), (s, s), (s, -s)):  # clockwise from above: faces down
            f.write("v %.9g %.9g %.9g\n" % (x, y, height))
        n = len(points)
        f.write("o gear\nusemtl grey\nf %s\n" % " ".join(str(k + 1) for k in range(n)))
        f.write("o lamp\nusemtl light\nf %s\n" % " ".join(str(n + k + 1) for k in range(4)))


if __name__ == "__main__":
    main()
