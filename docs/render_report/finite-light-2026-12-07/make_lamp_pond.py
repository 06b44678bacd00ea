#!/usr/bin/env python3
"""The deep pond (absorption-2026-12-06/make_deep_pond.py, 96 x 24 x 96, u8, x fastest, then y,
then z) with lamps: an 8 x 1 x 8 slab of lamp blocks 5 blocks over the pond's surface (x 44..51,
y 18, z 40..47) and two posts of two lamps on the bank (x, z = 10, 30 and 85, 60). At night
(`--sun off --sky-light 0`) the floor under water takes the area light and the lamps' faces, both
bent at the surface (finite-light-2026-12-07, render_report.md).
Usage: make_lamp_pond.py OUT.raw"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
from deep_pond import deep_pond, put, save  # noqa: E402

LAMP = 8
out = sys.argv[1]
vol = deep_pond(out)
for z in range(40, 48):
    for x in range(44, 52):
        put(vol, x, 18, z, LAMP)
for x, z in ((10, 30), (85, 60)):
    for y in (14, 15):
        put(vol, x, y, z, LAMP)
save(vol, out)
