#!/usr/bin/env python3
"""Open meshes that are the solid fill's hardest case (docs/voxelize.md,
"Soups and foliage"): almost every edge a boundary, so the winding rule's
caps are as many as the triangles and cover the whole box.

  make_soup.py soup N OUT.stl       N separate random triangles in the unit
                                    cube (binary STL: no shared corners)
  make_soup.py foliage N OUT.obj    a tree: N leaf cards (two triangles each,
                                    random size and tilt) in a crown, on a
                                    closed box trunk

Both are deterministic (fixed seed), so a benchmark or a memory figure made
from them is repeatable.
"""
import math
import random
import struct
import sys


def soup(n, out):
    rng = random.Random(1)
    with open(out, "wb") as f:
        f.write(b"random triangle soup".ljust(80, b" "))
        f.write(struct.pack("<I", n))
        for _ in range(n):
            c = [rng.random() for _ in range(3)]
            tri = []
            for _ in range(3):
                tri += [c[k] + rng.uniform(-0.06, 0.06) for k in range(3)]
            f.write(struct.pack("<3f", 0.0, 0.0, 0.0))
            f.write(struct.pack("<9f", *tri))
            f.write(b"\0\0")


def foliage(n, out):
    rng = random.Random(2)
    v = []
    faces = []
    # trunk: a closed box from the ground to the crown's centre
    w = 0.06
    for z in (0.0, 0.55):
        for x, y in ((-w, -w), (w, -w), (w, w), (-w, w)):
            v.append((0.5 + x, 0.5 + y, z))
    quads = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    for a, b, c, d in quads:
        faces += [(a, b, c), (a, c, d)]
    # leaves: cards in a sphere of radius 0.35 around (0.5, 0.5, 0.6)
    for _ in range(n):
        while True:
            p = [rng.uniform(-1, 1) for _ in range(3)]
            if sum(x * x for x in p) <= 1:
                break
        centre = (0.5 + 0.35 * p[0], 0.5 + 0.35 * p[1], 0.6 + 0.35 * p[2])
        size = rng.uniform(0.015, 0.04)
        yaw = rng.uniform(0, 2 * math.pi)
        tilt = rng.uniform(-1.2, 1.2)
        u = (math.cos(yaw), math.sin(yaw), 0.0)
        t = (-math.sin(yaw) * math.cos(tilt), math.cos(yaw) * math.cos(tilt), math.sin(tilt))
        base = len(v)
        for su, st in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            v.append(tuple(centre[k] + size * (su * u[k] + 0.5 * st * t[k]) for k in range(3)))
        faces += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
    with open(out, "w") as f:
        for x, y, z in v:
            f.write("v %.6f %.6f %.6f\n" % (x, y, z))
        for a, b, c in faces:
            f.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))


def main():
    if len(sys.argv) != 4 or sys.argv[1] not in ("soup", "foliage"):
        sys.stderr.write(__doc__)
        sys.exit(2)
    (soup if sys.argv[1] == "soup" else foliage)(int(sys.argv[2]), sys.argv[3])


if __name__ == "__main__":
    main()
