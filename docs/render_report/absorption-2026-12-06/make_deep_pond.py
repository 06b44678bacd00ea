#!/usr/bin/env python3
"""A raw volume (u8, 96 x 24 x 96, x fastest, then y, then z) of the default palette: grass on dirt
with its top at y = 14, a pond over x, z 16..79 whose water deepens from 1 block at its near shore
(z = 16) to 11 at its far half (a step every 5 blocks), on a sand floor, and a stone pillar standing
in it (absorption-2026-12-06, render_report.md: Beer-Lambert absorption shows as depth).
Usage: make_deep_pond.py OUT.raw"""
import sys
X, Y, Z = 96, 24, 96
DIRT, GRASS, SAND, WATER, STONE = 2, 3, 4, 5, 1
vol = bytearray(X * Y * Z)
def put(x, y, z, b): vol[x + X * (y + Y * z)] = b
for z in range(Z):
    for x in range(X):
        pond = 16 <= x < 80 and 16 <= z < 80
        for y in range(14):
            put(x, y, z, DIRT if y < 13 else GRASS)
        if pond:
            depth = 1 + min(10, (z - 16) // 5)  # 1 block at the near shore to 11 far
            for y in range(13 - depth + 1, 14):
                put(x, y, z, WATER)
            put(x, 13 - depth, z, SAND)
for y in range(2, 20):
    for dx in range(2):
        for dz in range(2):
            put(48 + dx, y, 60 + dz, STONE)
open(sys.argv[1], 'wb').write(vol)
