#!/usr/bin/env python3
"""A raw volume (u8, 256 x 48 x 256, x fastest, then y, then z) for timing the shadow rays' pairing
of touching see-through faces (stop 55): the scattered volume of
../raster-transparency-2026-12-05/make_scatter.py (rolling stone ground topped with grass, 10% of
the cells of y 20..43 scattered, the same random draws), each scattered cell water (5) or glass (6)
by a second draw. About one scattered cell in five then touches one of the other kind: every ray
the frame traces takes the probing variant, and shadow rays through the scatter meet marked faces."""
import os
import random
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "raster-transparency-2026-12-05"))
from make_scatter import X, Y, Z, scattered  # noqa: E402

out = sys.argv[1] if len(sys.argv) > 1 else "."
vol = scattered(5)
pick = random.Random(11)
for i, v in enumerate(vol):
    if v == 5 and pick.random() < 0.5:
        vol[i] = 6
with open(f"{out}/scatter_mixed.raw", "wb") as f:
    f.write(vol)
