#!/usr/bin/env python3
"""Prints what a .glb or .gltf holds as JSON, read with the standard library
only (the tests compare it with hand-computed values):

  {"primitives": [{"material": NAME, "vertices": N, "indices": N or null,
                   "index_type": 5123 or 5125 or null, "min": [...], "max": [...]}],
   "materials": [NAME...], "buffer_bytes": N, "nodes": N}

Usage: gltf_summary.py FILE.glb|FILE.gltf
"""
import json
import struct
import sys


def load(path):
    data = open(path, "rb").read()
    if path.endswith(".glb"):
        magic, version, length = struct.unpack_from("<III", data, 0)
        assert magic == 0x46546C67 and version == 2, "not a glTF 2 binary"
        assert length == len(data), f"header length {length} != file size {len(data)}"
        json_len, json_type = struct.unpack_from("<II", data, 12)
        assert json_type == 0x4E4F534A
        doc = json.loads(data[20:20 + json_len])
        rest = data[20 + json_len:]
        if rest:
            bin_len, bin_type = struct.unpack_from("<II", rest, 0)
            assert bin_type == 0x004E4942 and bin_len == len(rest) - 8
        return doc
    return json.load(open(path))


def main():
    doc = load(sys.argv[1])
    acc = doc.get("accessors", [])
    mats = [m.get("name") for m in doc.get("materials", [])]
    prims = []
    for mesh in doc.get("meshes", []):
        for p in mesh["primitives"]:
            pos = acc[p["attributes"]["POSITION"]]
            for name in ("NORMAL", "COLOR_0", "TEXCOORD_0"):
                assert acc[p["attributes"][name]]["count"] == pos["count"], name
            idx = acc[p["indices"]] if "indices" in p else None
            prims.append({"material": mats[p["material"]], "vertices": pos["count"],
                          "indices": idx["count"] if idx else None,
                          "index_type": idx["componentType"] if idx else None,
                          "min": pos["min"], "max": pos["max"]})
    print(json.dumps({"primitives": prims, "materials": mats, "nodes": len(doc.get("nodes", [])),
                      "buffer_bytes": sum(b["byteLength"] for b in doc.get("buffers", []))}))


if __name__ == "__main__":
    main()
