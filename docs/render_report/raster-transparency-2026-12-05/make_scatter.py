#!/usr/bin/env python3
"""Two raw volumes (u8, 256 x 48 x 256, x fastest, then y, then z) with the same geometry: rolling
stone ground topped with grass, and 10% of the cells of y 20..43 scattered with one block id:
stone (1) in scatter_stone.raw, water (5, see-through) in scatter_water.raw. The raster baseline
draws the first in one pass and the second in two (its transparent pass)."""
import math
import random
import sys

X, Y, Z = 256, 48, 256


def ground_height(x, z):
    return int(6 + 4 * math.sin(x * 0.07) + 4 * math.cos(z * 0.05))


def scattered(scatter_id):
    """The volume with `scatter_id` scattered (the same random draws for every id)."""
    random.seed(7)
    vol = bytearray(X * Y * Z)
    for z in range(Z):
        for x in range(X):
            h = ground_height(x, z)
            for y in range(h):
                vol[x + X * (y + Y * z)] = 1 if y < h - 1 else 3
    for z in range(Z):
        for y in range(20, 44):
            for x in range(X):
                if random.random() < 0.10:
                    vol[x + X * (y + Y * z)] = scatter_id
    return vol


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "."
    for name, scatter_id in (("stone", 1), ("water", 5)):
        with open(f"{out}/scatter_{name}.raw", "wb") as f:
            f.write(scattered(scatter_id))
