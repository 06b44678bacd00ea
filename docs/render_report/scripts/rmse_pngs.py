"""RMSE of 8-bit PNGs against a reference PNG, over RGB in [0, 1] (the device scripts' one-frame
error). Usage: python3 rmse_pngs.py REF.png IMAGE.png ...; one line per image."""
import os
import sys

import numpy as np
from PIL import Image


def load(path):
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    ref = load(sys.argv[1])
    for path in sys.argv[2:]:
        print("rmse %-14s %.6f" % (os.path.basename(path), np.sqrt(np.mean((load(path) - ref) ** 2))))


if __name__ == "__main__":
    main()
