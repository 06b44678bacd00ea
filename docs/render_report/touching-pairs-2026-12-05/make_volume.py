#!/usr/bin/env python3
"""A raw volume (u8, 256 x 48 x 256, x fastest, then y, then z) for the touching-pairs timing: the
water volume of ../raster-transparency-2026-12-05/make_scatter.py (rolling stone ground topped
with grass, 10% of the cells of y 20..43 water, the same random draws), plus glass (6) standing on
the ground in the cells beside every chunk border plane x = 32k, every fourth z. Glass and water
then both have faces on chunk border planes, and none touch (the ground is below y 15, the water
above y 19): the bound before stop 50 traced every ray with the probe, the pairs trace none."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "raster-transparency-2026-12-05"))
from make_scatter import X, Y, Z, ground_height, scattered  # noqa: E402

out = sys.argv[1] if len(sys.argv) > 1 else "."
vol = scattered(5)
for z in range(0, Z, 4):
    for x in range(31, X, 32):
        for gx in (x, x + 1):
            if gx < X:
                vol[gx + X * (ground_height(gx, z) + Y * z)] = 6
with open(f"{out}/water_glass.raw", "wb") as f:
    f.write(vol)
