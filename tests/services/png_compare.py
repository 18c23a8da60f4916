#!/usr/bin/env python3
"""PSNR of two 8-bit PNG renders (RGB or RGBA) over the pixels no photograph covers (alpha 0 in
the first), or over every pixel when it has no alpha (`histoview render` writes RGB), with
Python's standard library only.

    png_compare.py A.png B.png [--min-pixels N]

Prints "PSNR X dB over N pixels" (X "inf" when identical there) and exits 0; exits 1 when
fewer than N (default 1) pixels are compared, or the sizes differ."""
import math
import struct
import sys
import zlib


def read_png(path):
    d = open(path, "rb").read()
    if d[:8] != b"\x89PNG\r\n\x1a\n":
        raise SystemExit(f"{path}: not a PNG")
    pos, idat = 8, b""
    while pos < len(d):
        n, t = struct.unpack(">I4s", d[pos:pos + 8])
        c = d[pos + 8:pos + 8 + n]
        if t == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", c[:10])
            if depth != 8 or ctype not in (2, 6):
                raise SystemExit(f"{path}: expected 8-bit RGB or RGBA")
        elif t == b"IDAT":
            idat += c
        pos += 12 + n
    ch = 4 if ctype == 6 else 3
    raw, stride = zlib.decompress(idat), w * ch
    rows, prev, p = [], bytearray(stride), 0
    for _ in range(h):
        f, line = raw[p], bytearray(raw[p + 1:p + 1 + stride])
        p += 1 + stride
        for i in range(stride):
            a = line[i - ch] if i >= ch else 0
            b = prev[i]
            c = prev[i - ch] if i >= ch else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return w, h, ch, rows


def main():
    args = sys.argv[1:]
    min_pixels = 1
    if "--min-pixels" in args:
        k = args.index("--min-pixels")
        min_pixels = int(args[k + 1])
        del args[k:k + 2]
    (wa, ha, ca, a), (wb, hb, cb, b) = read_png(args[0]), read_png(args[1])
    if (wa, ha) != (wb, hb):
        print(f"sizes differ: {wa}x{ha} and {wb}x{hb}")
        return 1
    se, n = 0, 0
    for y in range(ha):
        ra, rb = a[y], b[y]
        for x in range(wa):
            if ca == 4 and ra[x * 4 + 3] != 0:
                continue
            for k in range(3):
                d = ra[x * ca + k] - rb[x * cb + k]
                se += d * d
            n += 1
    if n < min_pixels:
        print(f"only {n} pixels compared (expected at least {min_pixels})")
        return 1
    mse = se / (3 * n)
    db = "inf" if mse == 0 else f"{10 * math.log10(255 * 255 / mse):.2f}"
    print(f"PSNR {db} dB over {n} pixels" + (" no photograph covers" if ca == 4 else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
