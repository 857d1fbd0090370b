#!/usr/bin/env python3
"""Writes the small glTF files of the glTF-extension tests (tests/cli/gltfext_test.sh).

Each extension's file comes with a plain file that must voxelize to the same
voxels (the oracle): the extension applied by hand here, in exact arithmetic.

  make_gltf.py draco-source OUT.gltf       integer-grid box + slanted triangle, per-triangle UVs and colours
  make_gltf.py quantized OUT.gltf          KHR_mesh_quantization: SHORT positions, UNSIGNED_BYTE normalized UVs
  make_gltf.py quantized-ref OUT.gltf      the same mesh with FLOAT accessors
  make_gltf.py transform OUT.gltf          KHR_texture_transform (offset, rotation, scale, texCoord override)
  make_gltf.py transform-ref OUT.gltf      the same with the transform applied to the UVs
  make_gltf.py instancing OUT.gltf         EXT_mesh_gpu_instancing: 4 instances (T, R, S)
  make_gltf.py instancing-ref OUT.gltf     one node per instance
  make_gltf.py specgloss OUT.gltf          KHR_materials_pbrSpecularGlossiness diffuse factor and texture
  make_gltf.py specgloss-ref OUT.gltf      the same as baseColorFactor and baseColorTexture
  make_gltf.py required EXT[,EXT] OUT.gltf the textured box requiring the extensions ("" for none)
  make_gltf.py png OUT.png                 the quadrant texture
  make_gltf.py webp MODE IN.webp OUT.gltf  the required "" box textured by IN.webp (MODE only, fallback, corrupt)
  make_gltf.py corrupt KIND IN.glb OUT.glb a Draco GLB broken one way (truncated, attribute-id, bufferview)
"""
import base64
import json
import math
import struct
import sys
import zlib

FLOAT, BYTE, UBYTE, SHORT, USHORT, UINT = 5126, 5120, 5121, 5122, 5123, 5125
FMT = {FLOAT: "f", BYTE: "b", UBYTE: "B", SHORT: "h", USHORT: "H", UINT: "I"}
NCOMP = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


def png(width, height, rgba_rows):
    """An 8-bit RGBA PNG of `rgba_rows` (rows of (r, g, b, a) tuples)."""
    raw = b"".join(b"\0" + bytes(c for px in row for c in px) for row in rgba_rows)

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


# A 4x4 texture of four uniform 2x2 quadrants: sampled at a quadrant's centre
# (u, v in {0.25, 0.75}) any filter gives the quadrant's colour exactly.
QUADRANTS = [[(255, 0, 0, 255), (0, 255, 0, 255)], [(0, 0, 255, 255), (255, 255, 0, 255)]]
TEXTURE = png(4, 4, [[QUADRANTS[y // 2][x // 2] for x in range(4)] for y in range(4)])


class Gltf:
    def __init__(self):
        self.doc = {"asset": {"version": "2.0", "generator": "voxbake tests/gltfext/make_gltf.py"},
                    "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "accessors": [],
                    "bufferViews": [], "buffers": []}
        self.bin = bytearray()

    def view(self, data):
        while len(self.bin) % 4:
            self.bin.append(0)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)})
        self.bin += data
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, values, kind, ctype=FLOAT, normalized=False):
        n = NCOMP[kind]
        size = struct.calcsize("<" + FMT[ctype])
        pad = -(n * size) % 4  # vertex attributes start on 4-byte boundaries
        if kind == "SCALAR":
            pad = 0
        data = b"".join(struct.pack("<%d%s" % (n, FMT[ctype]), *(v if n > 1 else [v])) + b"\0" * pad for v in values)
        a = {"bufferView": self.view(data), "componentType": ctype, "count": len(values), "type": kind}
        if pad:
            self.doc["bufferViews"][-1]["byteStride"] = n * size + pad
        if normalized:
            a["normalized"] = True
        if kind == "VEC3" and ctype != UINT:  # POSITION needs min/max
            a["min"] = [min(v[i] for v in values) for i in range(3)]
            a["max"] = [max(v[i] for v in values) for i in range(3)]
        self.doc["accessors"].append(a)
        return len(self.doc["accessors"]) - 1

    def textured_material(self, extra=None, nearest=True):
        d = self.doc
        d["images"] = [{"bufferView": self.view(TEXTURE), "mimeType": "image/png"}]
        d["samplers"] = [{"magFilter": 9728 if nearest else 9729, "minFilter": 9728 if nearest else 9729}]
        d["textures"] = [{"source": 0, "sampler": 0}]
        tex = {"index": 0}
        if extra:
            tex.update(extra)
        d.setdefault("materials", []).append({"name": "quadrants", "pbrMetallicRoughness": {"baseColorTexture": tex}})
        return len(d["materials"]) - 1

    def mesh(self, attributes, indices=None, material=None, name="m"):
        prim = {"attributes": attributes}
        if indices is not None:
            prim["indices"] = indices
        if material is not None:
            prim["material"] = material
        self.doc["meshes"].append({"name": name, "primitives": [prim]})
        return len(self.doc["meshes"]) - 1

    def node(self, **kw):
        self.doc["nodes"].append(kw)
        self.doc["scenes"][0]["nodes"].append(len(self.doc["nodes"]) - 1)
        return len(self.doc["nodes"]) - 1

    def write(self, path):
        self.doc["buffers"] = [{"byteLength": len(self.bin),
                                "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(self.bin)).decode()}]
        with open(path, "w") as f:
            json.dump(self.doc, f, indent=1)


def box_triangles(lo, hi):
    """The 12 triangles of an axis-aligned box, counter-clockwise seen from outside."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    c = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    quads = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (3, 7, 6, 2), (0, 4, 7, 3), (1, 2, 6, 5)]
    tris = []
    for a, b, cc, d in quads:
        tris += [(c[a], c[b], c[cc]), (c[a], c[cc], c[d])]
    return tris


def draco_source(out):
    """Positions on the integer grid with x spanning exactly 0..2047, so Draco's
    11-bit quantization (step = range / 2047 = 1) reproduces them exactly;
    every triangle has its own three vertices with one UV (a quadrant centre)
    and one colour (k/255), so sampling cannot straddle a texel edge."""
    tris = box_triangles((0, 0, 0), (2047, 1023, 1535)) + [((100, 200, 300), (1900, 900, 100), (700, 50, 1400))]
    uvs = [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)]
    palette = [(1.0, 0.0, 0.0, 1.0), (0.0, 1.0, 0.0, 1.0), (0.0, 0.0, 1.0, 1.0), (1.0, 1.0, 1.0, 1.0), (0.0, 0.0, 0.0, 1.0)]
    pos, uv, col = [], [], []
    for i, t in enumerate(tris):
        for p in t:
            pos.append(p)
            uv.append(uvs[i % 4])
            col.append(palette[i % 5])
    g = Gltf()
    mat = g.textured_material()
    m = g.mesh({"POSITION": g.accessor(pos, "VEC3"), "TEXCOORD_0": g.accessor(uv, "VEC2"),
                "COLOR_0": g.accessor(col, "VEC4")}, g.accessor(list(range(len(pos))), "SCALAR", UINT), mat, "grid")
    g.node(mesh=m, name="grid")
    g.write(out)


QUADRANT_CENTRES = [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)]


def soup(tris, uvs_of_triangle):
    """Unshared vertices: positions and, per triangle, one UV for its three corners."""
    pos, uv = [], []
    for i, t in enumerate(tris):
        for p in t:
            pos.append(p)
            uv.append(uvs_of_triangle(i))
    return pos, uv


def quantized(out, reference):
    """KHR_mesh_quantization: a box with SHORT integer positions and
    UNSIGNED_BYTE normalized UVs (k/255 near the quadrant centres), and a box
    of normalized BYTE positions (+-127 -> +-1, exact) scaled by its node; the
    reference stores the same values as FLOAT."""
    pos, _ = soup(box_triangles((0, 0, 0), (100, 60, 80)), lambda i: None)
    uv_bytes = [(64, 64), (191, 64), (64, 191), (191, 191)]
    uv = [uv_bytes[(i // 3) % 4] for i in range(len(pos))]
    unit, _ = soup(box_triangles((-127, -127, -127), (127, 127, 127)), lambda i: None)
    g = Gltf()
    mat = g.textured_material()
    if reference:
        a = g.mesh({"POSITION": g.accessor([tuple(float(c) for c in p) for p in pos], "VEC3"),
                    "TEXCOORD_0": g.accessor([(x / 255, y / 255) for x, y in uv], "VEC2")}, None, mat, "short")
        b = g.mesh({"POSITION": g.accessor([tuple(c / 127 for c in p) for p in unit], "VEC3")}, None, None, "byte")
    else:
        g.doc["extensionsUsed"] = g.doc["extensionsRequired"] = ["KHR_mesh_quantization"]
        a = g.mesh({"POSITION": g.accessor(pos, "VEC3", SHORT), "TEXCOORD_0": g.accessor(uv, "VEC2", UBYTE, True)},
                   None, mat, "short")
        b = g.mesh({"POSITION": g.accessor(unit, "VEC3", BYTE, True)}, None, None, "byte")
    g.node(mesh=a, name="short")
    g.node(mesh=b, name="byte", translation=[200, 30, 40], scale=[50, 50, 50])
    g.write(out)


# KHR_texture_transform of the test: offset, rotation (radians, counter-clockwise
# in UV space) and scale; uv' = T(offset) * R(rotation) * S(scale) * uv.
OFFSET, ROTATION, SCALE = (0.1, -0.2), 0.3, (1.5, 0.8)


def forward(u, v):
    c, s = math.cos(ROTATION), math.sin(ROTATION)
    return (c * SCALE[0] * u + s * SCALE[1] * v + OFFSET[0], -s * SCALE[0] * u + c * SCALE[1] * v + OFFSET[1])


def inverse(u, v):
    c, s = math.cos(ROTATION), math.sin(ROTATION)
    x, y = u - OFFSET[0], v - OFFSET[1]
    return ((c * x - s * y) / SCALE[0], (s * x + c * y) / SCALE[1])


def transform(out, reference):
    """KHR_texture_transform with a texCoord override: the file's TEXCOORD_1
    holds UVs whose transform lands on the quadrant centres (TEXCOORD_0 holds
    decoys the override must skip); the reference holds those centres as
    TEXCOORD_0 and no transform."""
    tris = box_triangles((0, 0, 0), (90, 50, 70))
    centres = lambda i: QUADRANT_CENTRES[(i * 3 + i // 4) % 4]
    pos, target = soup(tris, centres)
    g = Gltf()
    if reference:
        mat = g.textured_material()
        m = g.mesh({"POSITION": g.accessor(pos, "VEC3"), "TEXCOORD_0": g.accessor(target, "VEC2")}, None, mat, "box")
    else:
        g.doc["extensionsUsed"] = g.doc["extensionsRequired"] = ["KHR_texture_transform"]
        mat = g.textured_material({"texCoord": 0, "extensions": {"KHR_texture_transform": {
            "offset": list(OFFSET), "rotation": ROTATION, "scale": list(SCALE), "texCoord": 1}}})
        source = [inverse(*t) for t in target]
        assert all(abs(a - b) < 1e-12 for t, src in zip(target, source) for a, b in zip(t, forward(*src)))
        decoys = [(0.9, 0.1)] * len(pos)
        m = g.mesh({"POSITION": g.accessor(pos, "VEC3"), "TEXCOORD_0": g.accessor(decoys, "VEC2"),
                    "TEXCOORD_1": g.accessor(source, "VEC2")}, None, mat, "box")
    g.node(mesh=m, name="box")
    g.write(out)


# EXT_mesh_gpu_instancing of the test: translation, rotation (unit quaternion
# x, y, z, w) and scale per instance; one mirrors (negative scale).
def f32(values):
    """The values as float32 accessors hold them (so the reference's JSON
    numbers are the very same doubles)."""
    return tuple(struct.unpack("<f", struct.pack("<f", v))[0] for v in values)


INSTANCES = [tuple(f32(x) for x in inst) for inst in [
    ((0, 0, 0), (0, 0, 0, 1), (1, 1, 1)),
    ((40, 0, 0), (0, 0.38268343236508984, 0, 0.9238795325112867), (1, 2, 1)),
    ((0, 0, 50), (0.5, 0.5, 0.5, 0.5), (0.5, 0.5, 0.5)),
    ((60, 20, 60), (0, 0, 0, 1), (-1, 1, 1))]]


def instancing(out, reference):
    """EXT_mesh_gpu_instancing under a parent and a node transform; the
    reference has one child node per instance with the instance's TRS."""
    tris = box_triangles((0, 0, 0), (10, 12, 8))
    pos = [p for t in tris for p in t]
    g = Gltf()
    m = g.mesh({"POSITION": g.accessor(pos, "VEC3")}, None, None, "box")
    node = {"name": "forest", "translation": [5, 0, -3], "rotation": [0, 0, 0.25881904510252074, 0.9659258262890683]}
    if reference:
        g.doc["nodes"] = [{"name": "root", "translation": [100, 0, 0], "children": [1]}, dict(node, children=[2, 3, 4, 5])]
        for t, r, s in INSTANCES:
            g.doc["nodes"].append({"mesh": m, "translation": list(t), "rotation": list(r), "scale": list(s)})
    else:
        g.doc["extensionsUsed"] = g.doc["extensionsRequired"] = ["EXT_mesh_gpu_instancing"]
        ext = {"attributes": {"TRANSLATION": g.accessor([t for t, _, _ in INSTANCES], "VEC3"),
                              "ROTATION": g.accessor([r for _, r, _ in INSTANCES], "VEC4"),
                              "SCALE": g.accessor([s for _, _, s in INSTANCES], "VEC3")}}
        g.doc["nodes"] = [{"name": "root", "translation": [100, 0, 0], "children": [1]},
                          dict(node, mesh=m, extensions={"EXT_mesh_gpu_instancing": ext})]
    g.doc["scenes"][0]["nodes"] = [0]
    g.write(out)


def required(ext, out, webp=None, fallback=False):
    """The quadrant-textured box requiring `ext` (comma-separated names) and
    using KHR_materials_clearcoat and KHR_materials_sheen on its material."""
    tris = box_triangles((0, 0, 0), (30, 20, 10))
    pos, uv = soup(tris, lambda i: QUADRANT_CENTRES[i % 4])
    g = Gltf()
    mat = g.textured_material()
    g.doc["materials"][mat]["extensions"] = {"KHR_materials_clearcoat": {"clearcoatFactor": 1},
                                             "KHR_materials_sheen": {"sheenColorFactor": [1, 0, 0]}}
    names = [e for e in ext.split(",") if e]
    g.doc["extensionsUsed"] = names + ["KHR_materials_clearcoat", "KHR_materials_sheen"]
    if names:
        g.doc["extensionsRequired"] = names
    m = g.mesh({"POSITION": g.accessor(pos, "VEC3"), "TEXCOORD_0": g.accessor(uv, "VEC2")}, None, mat, "box")
    g.node(mesh=m, name="box")
    if webp is not None:
        g.doc["images"].append({"bufferView": g.view(webp), "mimeType": "image/webp"})
        g.doc["textures"][0] = {"sampler": 0, "extensions": {"EXT_texture_webp": {"source": len(g.doc["images"]) - 1}}}
        if fallback:  # image 0 becomes a black PNG, the texture's fallback source
            g.doc["images"][0] = {"bufferView": g.view(png(1, 1, [[(0, 0, 0, 255)]])), "mimeType": "image/png"}
            g.doc["textures"][0]["source"] = 0
        g.doc["extensionsUsed"].append("EXT_texture_webp")
    g.write(out)


def specgloss(out, reference):
    """KHR_materials_pbrSpecularGlossiness: the base colour is its diffuseFactor
    x diffuseTexture (the metallic-roughness decoy factor, black, must be
    ignored); the reference has them as baseColorFactor and baseColorTexture."""
    pos, uv = soup(box_triangles((0, 0, 0), (40, 30, 20)), lambda i: QUADRANT_CENTRES[i % 4])
    g = Gltf()
    mat = g.textured_material()
    pbr = g.doc["materials"][mat]["pbrMetallicRoughness"]
    if reference:
        pbr["baseColorFactor"] = [0.5, 1, 0.25, 1]
    else:
        g.doc["extensionsUsed"] = ["KHR_materials_pbrSpecularGlossiness"]
        g.doc["materials"][mat] = {"name": "quadrants", "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]},
                                   "extensions": {"KHR_materials_pbrSpecularGlossiness": {
                                       "diffuseFactor": [0.5, 1, 0.25, 1], "diffuseTexture": {"index": 0},
                                       "specularFactor": [1, 1, 1], "glossinessFactor": 0.5}}}
    m = g.mesh({"POSITION": g.accessor(pos, "VEC3"), "TEXCOORD_0": g.accessor(uv, "VEC2")}, None, mat, "box")
    g.node(mesh=m, name="box")
    g.write(out)


def webp(mode, webp_file, out):
    """The box of `required ""` textured from the WebP `webp_file` (the
    quadrant texture, written by cwebp -lossless) through EXT_texture_webp:
    mode "only" (required, no fallback source), "fallback" (a black PNG as the
    texture's fallback source, which vox must not use) or "corrupt" (the WebP's
    bytes cut in half, required)."""
    data = open(webp_file, "rb").read()
    if mode == "corrupt":
        data = data[:len(data) // 2]
    required("EXT_texture_webp" if mode != "fallback" else "", out, webp=data, fallback=(mode == "fallback"))


def read_glb(path):
    b = open(path, "rb").read()
    length = struct.unpack("<I", b[12:16])[0]
    return json.loads(b[20:20 + length]), b[20 + length:]


def write_glb(path, doc, rest):
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    with open(path, "wb") as f:
        f.write(struct.pack("<IIIII", 0x46546C67, 2, 20 + len(text) + len(rest), len(text), 0x4E4F534A) + text + rest)


def corrupt(kind, src, out):
    """The Draco GLB `src` broken one way: its Draco bytes cut to a third
    (truncated), POSITION mapped to a Draco attribute id the data does not have
    (attribute-id), the extension's bufferView past the file's (bufferview),
    COLOR_0 stored uncompressed with fewer values than Draco points
    (uncompressed-count)."""
    doc, rest = read_glb(src)
    prim = doc["meshes"][0]["primitives"][0]
    ext = prim["extensions"]["KHR_draco_mesh_compression"]
    if kind == "truncated":
        view = doc["bufferViews"][ext["bufferView"]]
        view["byteLength"] = max(1, view["byteLength"] // 3)
    elif kind == "attribute-id":
        ext["attributes"]["POSITION"] = 9
    elif kind == "bufferview":
        ext["bufferView"] = len(doc["bufferViews"]) + 5
    elif kind == "uncompressed-count":  # COLOR_0 left to its accessor, which has too few values
        del ext["attributes"]["COLOR_0"]
        doc["accessors"][prim["attributes"]["COLOR_0"]]["count"] = 5
    else:
        sys.exit("make_gltf.py: unknown corruption " + kind)
    write_glb(out, doc, rest)


def draco_box(drc, out, oob=False):
    """A GLB whose one primitive is the Draco mesh `drc` (positions only, as
    Debian's draco_encoder writes an OBJ box with -cl 0 -qp 0: sequential
    connectivity, raw indices, float positions). With `oob`, the second corner
    of face 5 is patched to point 200, past the mesh's points."""
    data = bytearray(open(drc, "rb").read())
    assert data[:5] == b"DRACO", drc + ": not a Draco file"
    assert data[7] == 1 and data[8] == 0, drc + ": not a sequentially encoded mesh (encode with -cl 0)"
    at = 11  # magic, version (2), encoder type, method, flags (2)

    def varint():
        nonlocal at
        value, shift = 0, 0
        while True:
            b = data[at]
            at += 1
            value |= (b & 0x7F) << shift
            shift += 7
            if b < 0x80:
                return value

    faces, points = varint(), varint()
    assert data[at] == 1 and points < 256, drc + ": indices are not raw bytes"
    indices = at + 1
    assert all(i < points for i in data[indices:indices + 3 * faces])
    if oob:
        data[indices + 3 * 5 + 1] = 200
    rest = bytes(data) + b"\0" * (-len(data) % 4)
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
           "meshes": [{"name": "box", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "extensions": {
               "KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": 0}}}}]}],
           "extensionsUsed": ["KHR_draco_mesh_compression"], "extensionsRequired": ["KHR_draco_mesh_compression"],
           "accessors": [{"componentType": 5126, "count": points, "type": "VEC3", "min": [0, 0, 0], "max": [2, 3, 5]},
                         {"componentType": 5125, "count": 3 * faces, "type": "SCALAR"}],
           "buffers": [{"byteLength": len(rest)}], "bufferViews": [{"buffer": 0, "byteLength": len(data)}]}
    write_glb(out, doc, struct.pack("<II", len(rest), 0x004E4942) + rest)


def main(argv):
    kind = argv[1]
    if kind == "draco-source":
        draco_source(argv[2])
    elif kind in ("quantized", "quantized-ref"):
        quantized(argv[2], kind.endswith("-ref"))
    elif kind in ("transform", "transform-ref"):
        transform(argv[2], kind.endswith("-ref"))
    elif kind in ("instancing", "instancing-ref"):
        instancing(argv[2], kind.endswith("-ref"))
    elif kind in ("specgloss", "specgloss-ref"):
        specgloss(argv[2], kind.endswith("-ref"))
    elif kind == "webp":
        webp(argv[2], argv[3], argv[4])
    elif kind == "png":
        open(argv[2], "wb").write(TEXTURE)
    elif kind == "required":
        required(argv[2], argv[3])
    elif kind == "corrupt":
        corrupt(argv[2], argv[3], argv[4])
    elif kind in ("draco-box", "draco-box-oob"):
        draco_box(argv[2], argv[3], kind.endswith("-oob"))
    else:
        sys.exit("make_gltf.py: unknown kind " + kind)


if __name__ == "__main__":
    main(sys.argv)
