#!/usr/bin/env python3
"""A raw volume (u8, 256 x 48 x 256, x fastest, then y, then z) for the touching-pairs timing: the
water volume of ../raster-transparency-2026-12-05/make_scatter.py (rolling stone ground topped
with grass, 10% of the cells of y 20..43 water, the same random draws), plus glass (6) standing on
the ground in the cells beside every chunk border plane x = 32k, every fourth z. Glass and water
then both have faces on chunk border planes, and none touch (the ground is below y 15, the water
above y 19): the bound before stop 50 traced every ray with the probe, the pairs trace none."""
import math
import random
import sys

X, Y, Z = 256, 48, 256
out = sys.argv[1] if len(sys.argv) > 1 else "."
random.seed(7)
vol = bytearray(X * Y * Z)
heights = {}
for z in range(Z):
    for x in range(X):
        h = int(6 + 4 * math.sin(x * 0.07) + 4 * math.cos(z * 0.05))
        heights[(x, z)] = h
        for y in range(h):
            vol[x + X * (y + Y * z)] = 1 if y < h - 1 else 3
for z in range(Z):
    for y in range(20, 44):
        for x in range(X):
            if random.random() < 0.10:
                vol[x + X * (y + Y * z)] = 5
for z in range(0, Z, 4):
    for x in range(31, X, 32):
        for gx in (x, x + 1):
            if gx < X:
                vol[gx + X * (heights[(gx, z)] + Y * z)] = 6
with open(f"{out}/water_glass.raw", "wb") as f:
    f.write(vol)
