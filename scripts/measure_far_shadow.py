#!/usr/bin/env python3
"""Falsely shadowed pixels of a lit floor seen from far above, measured with `vx render`.

A 1280 x 1280 stone floor (one block thick, raw volume) under the default light (a square centred
above the floor, unoccluded) is rendered from DIST blocks straight above with one shadow sample per
pixel, and again with shadows off. The light is unoccluded, so a floor pixel whose shadowed value
is under half its unshadowed value lost its one shadow ray to the floor itself. Pixels that miss
the floor (sky) or are too dark to compare are left out.

Usage: scripts/measure_far_shadow.py VX DIST [DIST...]   (VK_DRIVER_FILES picks the device)
"""
import os
import struct
import subprocess
import sys
import tempfile
import zlib

SIZE = 1280
SKY = (196, 218, 249)  # sRGB of the default sky (0.55, 0.7, 0.95).


def read_png(path):
    """RGB rows of an 8-bit RGBA or RGB, non-interlaced PNG."""
    data = open(path, "rb").read()
    pos, idat, width, height, bpp = 8, b"", 0, 0, 4
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            width, height, _, colour = struct.unpack(">IIBB", body[:10])
            bpp = 4 if colour == 6 else 3
        elif kind == b"IDAT":
            idat += body
    raw, stride, rows = zlib.decompress(idat), width * bpp, []
    prev, p = bytearray(stride), 0
    for _ in range(height):
        f, line = raw[p], bytearray(raw[p + 1:p + 1 + stride])
        p += 1 + stride
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b, c = prev[x], prev[x - bpp] if x >= bpp else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append([tuple(line[x * bpp:x * bpp + 3]) for x in range(width)])
        prev = line
    return rows


def measure(vx, dist, work):
    raw = os.path.join(work, "floor.raw")
    if not os.path.exists(raw):
        open(raw, "wb").write(bytes([1]) * (SIZE * SIZE))  # Block 1: stone.
    half = SIZE // 2
    # fov 1.05 degrees: the view spans 600 blocks each side at 2^16, inside the floor.
    args = [vx, "render", "--raw", raw, "--dims", f"{SIZE},1,{SIZE}", "--eye", f"{half}.3,{dist},{half}.7",
            "--target", f"{half},0,{half}", "--up", "0,0,-1", "--fov", "1.05", "--size", "64x64",
            "--reflections", "0"]
    on, off = os.path.join(work, "on.png"), os.path.join(work, "off.png")
    subprocess.run(args + ["--spp", "1", "--out", on], check=True, capture_output=True)
    subprocess.run(args + ["--shadows", "off", "--out", off], check=True, capture_output=True)
    floor = shadowed = 0
    for row_on, row_off in zip(read_png(on), read_png(off)):
        for a, b in zip(row_on, row_off):
            if b == SKY or sum(b) < 24:
                continue
            floor += 1
            shadowed += sum(a) < 0.5 * sum(b)
    return shadowed, floor


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    with tempfile.TemporaryDirectory() as work:
        for dist in sys.argv[2:]:
            shadowed, floor = measure(sys.argv[1], dist, work)
            print(f"{dist} blocks: {shadowed} of {floor} floor pixels falsely shadowed "
                  f"({100.0 * shadowed / max(floor, 1):.2f}%)")


if __name__ == "__main__":
    main()
