#!/usr/bin/env python3
"""How two 8-bit PNGs of one size differ: the pixels that differ, the largest byte difference and
the RMSE over the RGB channels (0..1). Usage: compare_png.py A.png B.png [C.png ...]: each file
against the first. Pure Python (measure_sampling.read_png): a 1080p pair takes about a minute."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from measure_sampling import read_png  # noqa: E402


def compare(a, b):
    """(pixels differing, largest byte difference, RMSE) of two equal-size RGB float lists."""
    if len(a) != len(b):
        raise SystemExit("images of different sizes")
    differing, largest, squares = 0, 0, 0.0
    for i in range(0, len(a), 3):
        d = [abs(a[i + c] - b[i + c]) for c in range(3)]
        if any(x > 0 for x in d):
            differing += 1
        largest = max(largest, round(max(d) * 255))
        squares += sum(x * x for x in d)
    return differing, largest, math.sqrt(squares / len(a))


def main(paths):
    if len(paths) < 2:
        raise SystemExit(__doc__)
    first = read_png(paths[0])
    for p in paths[1:]:
        n, largest, rmse = compare(first, read_png(p))
        print(f"{p} against {paths[0]}: {n} of {len(first) // 3} pixels differ, by at most {largest}/255; "
              f"RMSE {rmse:.6f}")


if __name__ == "__main__":
    main(sys.argv[1:])
