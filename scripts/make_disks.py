#!/usr/bin/env python3
"""Writes an OBJ of two coaxial regular n-gon disks facing each other (issue 16's n-gon case).

usage: make_disks.py OUT.obj [CORNERS=128] [RADIUS=1] [DISTANCE=1]

The lower disk (z = 0) faces up and emits (material "light"), the upper (z = DISTANCE) faces
down. Their form factor has a closed form (Howell C-41): with R = RADIUS / DISTANCE,
X = 1 + (1 + R^2) / R^2, F = (X - sqrt(X^2 - 4)) / 2; for disks of the polygon's area use
R^2 = n sin(2 pi / n) / (2 pi) RADIUS^2 / DISTANCE^2."""
import math
import os
import sys


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 128
    radius = float(sys.argv[3]) if len(sys.argv) > 3 else 1.0
    distance = float(sys.argv[4]) if len(sys.argv) > 4 else 1.0
    mtl = os.path.splitext(out)[0] + ".mtl"
    with open(mtl, "w") as f:
        f.write("newmtl light\nKd 0.5 0.5 0.5\nKe 1 1 1\nnewmtl grey\nKd 0.5 0.5 0.5\n")
    with open(out, "w") as f:
        f.write("mtllib %s\n" % os.path.basename(mtl))
        for z in (0.0, distance):
            for k in range(n):
                a = 2 * math.pi * k / n
                f.write("v %.17g %.17g %.17g\n" % (radius * math.cos(a), radius * math.sin(a), z))
        f.write("o lower\nusemtl light\nf %s\n" % " ".join(str(k + 1) for k in range(n)))
        f.write("o upper\nusemtl grey\nf %s\n" % " ".join(str(n + n - k) for k in range(n)))


if __name__ == "__main__":
    main()
