#!/usr/bin/env python3
"""SHA-256 of an OpenEXR file's pixels: its scanline chunks (line and compressed data), not its
header, so that the recipe a render embeds (with each plugin binary's own hash) does not change
the value while the pixels stay the same. Scanline files only (what fixpoint writes untiled)."""
import hashlib
import struct
import sys


def pixel_hash(path):
    data = open(path, "rb").read()
    if data[:4] != b"\x76\x2f\x31\x01":
        raise SystemExit(f"{path}: not an OpenEXR file")
    pos = 8
    while data[pos] != 0:  # attributes: name\0 type\0 size value, up to an empty name
        pos = data.index(b"\0", pos) + 1
        pos = data.index(b"\0", pos) + 1
        (size,) = struct.unpack_from("<i", data, pos)
        pos += 4 + size
    pos += 1
    (first,) = struct.unpack_from("<Q", data, pos)
    chunks = (first - pos) // 8
    h = hashlib.sha256()
    at = first
    for _ in range(chunks):
        y, size = struct.unpack_from("<ii", data, at)
        h.update(data[at : at + 8 + size])
        at += 8 + size
    return h.hexdigest()


for p in sys.argv[1:]:
    print(pixel_hash(p))
