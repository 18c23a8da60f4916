#!/usr/bin/env python3
"""PSNR of two 8-bit PNG renders (RGB or RGBA) over the pixels no photograph covers (alpha 0 in
the first), or over every pixel when it has no alpha (`histoview render` writes RGB), with
Python's standard library only.

    png_compare.py A.png B.png [--min-pixels N]

Prints "PSNR X dB over N pixels" (X "inf" when identical there) and exits 0; exits 1 when
fewer than N (default 1) pixels are compared, or the sizes differ."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from png_read import decode_png  # noqa: E402


def read_png(path):
    width, height, channels, rows = decode_png(path)
    if channels not in (3, 4):
        raise SystemExit(f"{path}: expected 8-bit RGB or RGBA")
    return width, height, channels, rows


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
