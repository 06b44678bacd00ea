#!/usr/bin/env python3
"""A raw volume (u8, 96 x 24 x 96, x fastest, then y, then z) of the default palette: grass on dirt
with its top at y = 6, a pond (water at y 4..5, sand floor at y 3) over x, z 16..79, three stone
pillars and a glass pane standing in it, a lamp post on its far shore. Seen from a low eye at the
near shore: the pond's surface shows the sky at grazing angles, the pillars at their mirror images,
and its floor where the view is steep (water-surface-2026-12-06, render_report.md)."""
import sys

X, Y, Z = 96, 24, 96
STONE, DIRT, GRASS, SAND, WATER, GLASS, LAMP = 1, 2, 3, 4, 5, 6, 8


def main(path):
    vol = bytearray(X * Y * Z)

    def put(x, y, z, b):
        vol[x + X * (y + Y * z)] = b

    for z in range(Z):
        for x in range(X):
            pond = 16 <= x < 80 and 16 <= z < 80
            for y in range(6):
                put(x, y, z, DIRT if y < 5 else GRASS)
            if pond:
                put(x, 3, z, SAND)
                put(x, 4, z, WATER)
                put(x, 5, z, WATER)
    for px, pz, h in ((34, 52, 12), (50, 64, 16), (64, 46, 9)):
        for y in range(4, 6 + h):
            for dx in range(2):
                for dz in range(2):
                    put(px + dx, y, pz + dz, STONE)
    for x in range(40, 46):  # A glass pane standing in the water, across the view.
        for y in range(4, 10):
            put(x, y, 36, GLASS)
    for y in range(6, 14):
        put(48, y, 84, STONE if y < 13 else LAMP)
    with open(path, "wb") as f:
        f.write(vol)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "pond.raw")
