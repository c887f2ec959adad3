"""Fails unless every PNG given has at least MIN distinct colours (an image that is one colour
only, the background, shows nothing). Python's standard library only.

Usage: python3 png_colours.py MIN FILE..."""

import struct
import sys
import zlib


def pixels(path):
    """The pixels of an 8- or 16-bit grey, RGB or RGBA PNG (no interlacing), as byte strings."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise SystemExit(f"{path}: not a PNG")
    pos, idat = 8, b""
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos : pos + 4])
        kind, body = data[pos + 4 : pos + 8], data[pos + 8 : pos + 8 + n]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    channels = {0: 1, 2: 3, 4: 2, 6: 4}.get(colour)
    if channels is None or depth not in (8, 16) or interlace:
        raise SystemExit(f"{path}: colour type {colour}, depth {depth}, interlace {interlace} not handled")
    bpp = channels * depth // 8
    stride = width * bpp
    raw = zlib.decompress(idat)
    prev = bytearray(stride)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1 : (y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        for x in range(width):
            yield bytes(line[x * bpp : (x + 1) * bpp])
        prev = line


def main():
    least = int(sys.argv[1])
    bad = 0
    for path in sys.argv[2:]:
        colours = len(set(pixels(path)))
        print(f"{path}: {colours} colours")
        if colours < least:
            print(f"{path}: fewer than {least} colours: the image shows nothing", file=sys.stderr)
            bad += 1
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
