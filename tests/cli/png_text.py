#!/usr/bin/env python3
"""Rewrites one tEXt entry of a PNG, for tests that craft atlases and renders
whose metadata was changed after vox wrote them.

Usage: png_text.py IN.png OUT.png KEY [VALUE]   (no VALUE: the entry is removed)
"""
import struct
import sys
import zlib


def retext(src, dst, key, value):
    data = open(src, 'rb').read()
    out = bytearray(data[:8])
    p = 8
    while p < len(data):
        n, = struct.unpack('>I', data[p:p + 4])
        kind, body = data[p + 4:p + 8], data[p + 8:p + 8 + n]
        p += 12 + n
        if kind in (b'tEXt', b'iTXt', b'zTXt') and body.split(b'\0', 1)[0] == key.encode():
            if value is None:
                continue
            kind, body = b'tEXt', key.encode() + b'\0' + value.encode()
        out += struct.pack('>I', len(body)) + kind + body + struct.pack('>I', zlib.crc32(kind + body) & 0xffffffff)
    open(dst, 'wb').write(out)


if __name__ == '__main__':
    retext(sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4] if len(sys.argv) > 4 else None)
