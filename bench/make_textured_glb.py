#!/usr/bin/env python3
"""The textured model of scripts/bench_gltf.sh: a rippled sphere of about 15 k
triangles in five bands, each band a material with its own JPEG (or PNG, by
the files' extension) texture (embedded in the GLB's BIN chunk), and the same
model with its textures removed (same materials as plain colours).

  make_textured_glb.py OUT_TEXTURED.glb OUT_PLAIN.glb T0.jpg ... T4.jpg
  make_textured_glb.py --plain OUT.glb S R      untextured, S x R quads (2 S R triangles)
"""
import json
import math
import struct
import sys


def glb(path, doc, bin_):
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    bin_ += b"\0" * (-len(bin_) % 4)
    with open(path, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 28 + len(text) + len(bin_)))
        f.write(struct.pack("<II", len(text), 0x4E4F534A) + text)
        f.write(struct.pack("<II", len(bin_), 0x004E4942) + bin_)


def build(textures, S=96, R=80):  # 96 x 80 quads = 15 360 triangles
    bands = 5
    bin_ = bytearray()
    views, accessors, meshes = [], [], []

    def view(data):
        while len(bin_) % 4:
            bin_.append(0)
        views.append({"buffer": 0, "byteOffset": len(bin_), "byteLength": len(data)})
        bin_.extend(data)
        return len(views) - 1

    for b in range(bands):
        pos, uv, idx = [], [], []
        j0, j1 = b * R // bands, (b + 1) * R // bands
        for j in range(j0, j1 + 1):
            th = math.pi * j / R
            for i in range(S + 1):
                ph = 2 * math.pi * i / S
                r = 1 + 0.04 * math.sin(7 * th) * math.cos(5 * ph)
                pos += [r * math.sin(th) * math.cos(ph), r * math.cos(th), r * math.sin(th) * math.sin(ph)]
                uv += [i / S, (j - j0) / (j1 - j0)]
        W = S + 1
        for j in range(j1 - j0):
            for i in range(S):
                a, c = j * W + i, (j + 1) * W + i
                idx += [a, c, a + 1, a + 1, c, c + 1]
        n = len(pos) // 3
        attrs = {"POSITION": len(accessors)}
        accessors.append({"bufferView": view(struct.pack("<%df" % len(pos), *pos)), "componentType": 5126, "count": n,
                          "type": "VEC3", "min": [min(pos[k::3]) for k in range(3)],
                          "max": [max(pos[k::3]) for k in range(3)]})
        if textures:
            attrs["TEXCOORD_0"] = len(accessors)
            accessors.append({"bufferView": view(struct.pack("<%df" % len(uv), *uv)), "componentType": 5126,
                              "count": n, "type": "VEC2"})
        accessors.append({"bufferView": view(struct.pack("<%dI" % len(idx), *idx)), "componentType": 5125,
                          "count": len(idx), "type": "SCALAR"})
        meshes.append({"name": "band%d" % b, "primitives": [{"attributes": attrs, "indices": len(accessors) - 1,
                                                             "material": b}]})
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": list(range(bands))}],
           "nodes": [{"mesh": b, "name": "band%d" % b} for b in range(bands)], "meshes": meshes,
           "materials": [{"name": "m%d" % b, "pbrMetallicRoughness": {"baseColorFactor": [1, 0.9, 0.8, 1]}}
                         for b in range(bands)]}
    if textures:
        doc["images"] = [{"bufferView": view(open(t, "rb").read()),
                          "mimeType": "image/png" if t.lower().endswith(".png") else "image/jpeg"} for t in textures]
        doc["textures"] = [{"source": b} for b in range(bands)]
        for b in range(bands):
            doc["materials"][b]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": b}
    doc["accessors"], doc["bufferViews"] = accessors, views
    doc["buffers"] = [{"byteLength": len(bin_) + (-len(bin_) % 4)}]
    return doc, bytes(bin_)


if __name__ == "__main__":
    if sys.argv[1] == "--plain":
        glb(sys.argv[2], *build([], int(sys.argv[3]), int(sys.argv[4])))
    else:
        glb(sys.argv[1], *build(sys.argv[3:8]))
        glb(sys.argv[2], *build([]))
