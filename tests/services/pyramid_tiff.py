#!/usr/bin/env python3
"""A PNG photograph as a tiled pyramidal TIFF, the layout iipsrv serves (tests/iiif_test.sh).

    pyramid_tiff.py IN.png OUT.tif

Python's standard library only (no GDAL tools, vips or Pillow on the test machines): the PNG is
decoded here (8-bit grey, RGB or RGBA, not interlaced; alpha dropped), and the TIFF holds the full
resolution then halvings (2x2 box averages) down to one tile, each an IFD of 256 x 256 RGB tiles,
uncompressed (iipsrv re-encodes what it serves as JPEG anyway).
"""
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from png_read import decode_png  # noqa: E402

TILE = 256


def read_png(path):
    width, height, channels, rows = decode_png(path)
    rgb = bytearray(width * height * 3)
    for y, line in enumerate(rows):
        for x in range(width):
            s = line[x * channels:x * channels + channels]
            rgb[(y * width + x) * 3:(y * width + x) * 3 + 3] = bytes(s[:3]) if channels >= 3 else bytes(s) * 3
    return width, height, rgb


def halve(width, height, rgb):
    w, h = max(1, width // 2), max(1, height // 2)
    out = bytearray(w * h * 3)
    for y in range(h):
        for x in range(w):
            for c in range(3):
                s = 0
                for dy in (0, 1):
                    for dx in (0, 1):
                        yy, xx = min(2 * y + dy, height - 1), min(2 * x + dx, width - 1)
                        s += rgb[(yy * width + xx) * 3 + c]
                out[(y * w + x) * 3 + c] = (s + 2) // 4
    return w, h, out


def tiles(width, height, rgb):
    for ty in range(0, height, TILE):
        for tx in range(0, width, TILE):
            t = bytearray(TILE * TILE * 3)
            for y in range(min(TILE, height - ty)):
                n = min(TILE, width - tx) * 3
                src = ((ty + y) * width + tx) * 3
                t[y * TILE * 3:y * TILE * 3 + n] = rgb[src:src + n]
            yield bytes(t)


def write_tiff(path, levels):
    out = bytearray(b"II*\x00\x00\x00\x00\x00")
    ifd_offsets, link = [], 4
    for width, height, rgb in levels:
        offsets, counts = [], []
        for t in tiles(width, height, rgb):
            offsets.append(len(out))
            counts.append(len(t))
            out += t
        def array(values):  # LONG array, written out of line
            nonlocal out
            if len(out) % 2:
                out += b"\x00"
            at = len(out)
            out += struct.pack("<%dI" % len(values), *values)
            return at
        bps = len(out)
        out += struct.pack("<3H", 8, 8, 8)
        tile_offsets = array(offsets) if len(offsets) > 1 else offsets[0]
        tile_counts = array(counts) if len(counts) > 1 else counts[0]
        subfile = 0 if not ifd_offsets else 1  # reduced-resolution image
        entries = [
            (254, 4, 1, subfile), (256, 4, 1, width), (257, 4, 1, height), (258, 3, 3, bps),
            (259, 3, 1, 1), (262, 3, 1, 2), (277, 3, 1, 3), (284, 3, 1, 1),
            (322, 3, 1, TILE), (323, 3, 1, TILE),
            (324, 4, len(offsets), tile_offsets), (325, 4, len(counts), tile_counts),
        ]
        if len(out) % 2:
            out += b"\x00"
        at = len(out)
        struct.pack_into("<I", out, link, at)
        out += struct.pack("<H", len(entries))
        for tag, kind, count, value in entries:
            if kind == 3 and count == 1:
                out += struct.pack("<HHIHH", tag, kind, count, value, 0)
            else:
                out += struct.pack("<HHII", tag, kind, count, value)
        link = len(out)
        out += b"\x00\x00\x00\x00"
        ifd_offsets.append(at)
    open(path, "wb").write(out)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    width, height, rgb = read_png(sys.argv[1])
    levels = [(width, height, rgb)]
    while max(levels[-1][0], levels[-1][1]) > TILE:
        levels.append(halve(*levels[-1]))
    write_tiff(sys.argv[2], levels)


if __name__ == "__main__":
    main()
