#!/usr/bin/env python3
"""A large scan-like OBJ for the reader's benchmarks: a bumpy sphere of
N x M quads (2 N M triangles), positions with six decimals, plain "v x y z"
and "f a b c" lines, as scanners and exporters write them.

  make_bumpy_obj.py OUT.obj [N M]      default 1000 x 1000: 2 M triangles, 76 MB
"""
import math
import sys


def main():
    out = sys.argv[1]
    n1 = int(sys.argv[2]) if len(sys.argv) > 2 else 1000
    n2 = int(sys.argv[3]) if len(sys.argv) > 3 else 1000
    with open(out, "w") as f:
        for i in range(n1 + 1):
            th = math.pi * i / n1
            for j in range(n2):
                ph = 2 * math.pi * j / n2
                r = 1 + 0.05 * math.sin(7 * th) * math.cos(9 * ph)
                f.write("v %.6f %.6f %.6f\n" % (r * math.sin(th) * math.cos(ph), r * math.sin(th) * math.sin(ph),
                                                r * math.cos(th)))
        for i in range(n1):
            for j in range(n2):
                a = i * n2 + j + 1
                b = i * n2 + (j + 1) % n2 + 1
                c = (i + 1) * n2 + j + 1
                d = (i + 1) * n2 + (j + 1) % n2 + 1
                f.write("f %d %d %d\nf %d %d %d\n" % (a, c, b, b, c, d))


if __name__ == "__main__":
    main()
