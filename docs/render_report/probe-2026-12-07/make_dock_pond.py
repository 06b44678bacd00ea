#!/usr/bin/env python3
"""The deep pond (absorption-2026-12-06/make_deep_pond.py, 96 x 24 x 96, u8, x fastest, then y,
then z) with a stone dock under its surface: a slab one block thick at y = 11, two blocks under
the water's top (y = 14), over x 24..55, z 50..65, where the water is 7 to 10 deep. The floor under
the dock's edges takes the area light bent at the surface past the edge, though every way it
explores along the axes is shut (probe-2026-12-07, render_report.md).
Usage: make_dock_pond.py OUT.raw"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
from deep_pond import deep_pond, put, save  # noqa: E402

STONE = 1
out = sys.argv[1]
vol = deep_pond(out)
for z in range(50, 66):
    for x in range(24, 56):
        put(vol, x, 11, z, STONE)
save(vol, out)
