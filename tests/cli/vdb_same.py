#!/usr/bin/env python3
"""vdb_same.py A B: exit 0 when A (written without OpenVDB, e.g. by
formats/scene/scene_vdb_direct.h) has the bytes of B (written by OpenVDB's
io::File) but for the 36-character UUID (bytes 21..56) and the
`file_delayed_load` grid metadata OpenVDB adds (an optional index for delayed
loading that readers drop): B loses those entries and each grid's three stream
positions move back by the bytes removed, as tests/test_scene_vdb_direct.cpp
compares. Otherwise prints where they differ and exits 1."""
import struct
import sys

HDR, UUID_AT = 57, 21  # magic 8, versions 12, offsets flag 1, then the UUID


def strip_delayed_load(b):
    i32 = lambda at: struct.unpack_from('<i', b, at)[0]
    skip_str = lambda at: at + 4 + i32(at)

    def skip_entry(at):  # name, type name, int32 size, bytes
        at = skip_str(skip_str(at))
        return at + 4 + i32(at)

    p = HDR + 4
    for _ in range(i32(HDR)):  # file metadata
        p = skip_entry(p)
    grids = i32(p)
    p += 4
    out, shift = bytearray(b[:p]), 0
    for _ in range(grids):
        q = skip_str(skip_str(skip_str(p)))  # name, type, instance parent
        out += b[p:q]
        p = q
        pos = struct.unpack_from('<3q', b, p)  # grid, blocks, end
        at = len(out)
        out += b[p:p + 28]  # the positions and the compression flags
        grid_pos = pos[0] - shift
        n = i32(p + 28)
        p += 32
        kept, count = bytearray(), 0
        for _ in range(n):
            start, p = p, skip_entry(p)
            if b[start + 4:start + 4 + i32(start)] == b'file_delayed_load':
                shift += p - start
            else:
                kept += b[start:p]
                count += 1
        out += struct.pack('<i', count) + kept + b[p:pos[2]]
        p = pos[2]
        struct.pack_into('<3q', out, at, grid_pos, pos[1] - shift, pos[2] - shift)
    if p != len(b):
        sys.exit('%s: bytes after the last grid' % sys.argv[2])
    return bytes(out)


a = open(sys.argv[1], 'rb').read()
b = strip_delayed_load(open(sys.argv[2], 'rb').read())
if len(a) != len(b):
    sys.exit('%d bytes vs %d' % (len(a), len(b)))
if a[:UUID_AT] != b[:UUID_AT] or a[HDR:] != b[HDR:]:
    sys.exit('first differing byte at %d' % next(i for i in range(len(a)) if a[i] != b[i] and not UUID_AT <= i < HDR))
