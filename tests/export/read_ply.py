#!/usr/bin/env python3
"""Reads a binary little-endian PLY point cloud with numpy (not voxbake's code)
and prints it as JSON for the export tests:

  {"count": N, "properties": [...], "classes": {"ID": N}, "min": [x, y, z], "max": [...],
   "points": [[x, y, z, r, g, b, class], ...]}   (points sorted, only with --points)

Usage: read_ply.py FILE.ply [--points]
"""
import json
import sys

import numpy as np

TYPES = {"float": "<f4", "float32": "<f4", "uchar": "u1", "uint8": "u1", "int": "<i4", "double": "<f8"}


def main():
    data = open(sys.argv[1], "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    assert header[0] == "ply" and header[1] == "format binary_little_endian 1.0", header[:2]
    count, props = None, []
    for line in header:
        f = line.split()
        if f[0] == "element":
            assert f[1] == "vertex", "only a vertex element is expected"
            count = int(f[2])
        elif f[0] == "property":
            props.append((f[2], TYPES[f[1]]))
    points = np.frombuffer(data, dtype=np.dtype(props), count=count, offset=end)
    assert end + points.nbytes == len(data), "trailing bytes after the vertices"
    out = {"count": int(count), "properties": [p[0] for p in props]}
    ids, n = np.unique(points["class"], return_counts=True)
    out["classes"] = {str(int(i)): int(k) for i, k in zip(ids, n)}
    xyz = np.stack([points["x"], points["y"], points["z"]], axis=1).astype(np.float64)
    if count:
        out["min"] = xyz.min(axis=0).tolist()
        out["max"] = xyz.max(axis=0).tolist()
    if "--points" in sys.argv:
        rows = [[float(p["x"]), float(p["y"]), float(p["z"]), int(p["red"]), int(p["green"]), int(p["blue"]),
                 int(p["class"])] for p in points]
        out["points"] = sorted(rows)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
