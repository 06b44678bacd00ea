#!/usr/bin/env python3
"""One frame denoised against the same frame raw, by sample count, on three lavapipe scenes.

The denoiser's gain shrinks as samples grow, and past some count it adds error; this finds where
(docs/render_report.md, stop 40). Scenes: the glazed volume (a 10% random fill of glazed blocks,
64 x 32 x 64, the thesis's light, no reflections, 224x144: stop 27's), terrain (seed 1, radius 2,
160x96, default light) and issue 18's hidden-style scene (scripts/measure_one_frame.py's overview,
4 reflections, 112x72). Reference per scene: --spp 8 --accumulate 64 --history-clamp off with sample
seed 1000 (the plain mean of 512 samples per pixel). Prints, per scene, count and binary, the root
mean square over sample seeds 1 and 2 of the 8-bit images' RMSE, raw and denoised, and their ratio.

Usage: scripts/measure_denoiser_gain.py [--scenes glazed,terrain,hidden] [--spp 8,16,25] VX [OLD_VX]
  (VK_DRIVER_FILES picks the device; OLD_VX: a second binary, e.g. the base commit, measured
  against the same references, made with VX)
"""
import argparse
import math
import os
import random
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from measure_sampling import read_png, rmse  # noqa: E402
import measure_one_frame  # noqa: E402


def scenes(tmp):
    glazed = os.path.join(tmp, "glazed.raw")
    random.seed(7)
    with open(glazed, "wb") as f:
        f.write(bytes(12 if random.random() < 0.1 else 0 for _ in range(64 * 32 * 64)))
    hidden = os.path.join(tmp, "hidden.raw")
    measure_one_frame.scene(hidden)
    eye, target = measure_one_frame.VIEWS["overview"]
    return {
        "glazed": ["--raw", glazed, "--dims", "64,32,64", "--size", "224x144", "--lighting", "thesis",
                   "--reflections", "0"],
        "terrain": ["--seed", "1", "--radius", "2", "--size", "160x96"],
        "hidden": ["--raw", hidden, "--dims", "48,16,48", "--size", "112x72", "--eye", eye, "--target", target,
                   "--reflections", "4"],
    }


def render(vx, args, out):
    cmd = [vx, "render", *args, "--out", out]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"vx render failed: {' '.join(cmd)}\n{r.stdout}{r.stderr}")
    return read_png(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenes", default="glazed,terrain,hidden")
    ap.add_argument("--spp", default="8,16,25")
    ap.add_argument("vx", nargs="+")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        all_scenes = scenes(tmp)
        for name in a.scenes.split(","):
            base = all_scenes[name]
            ref = render(a.vx[0], base + ["--spp", "8", "--accumulate", "64", "--sample-seed", "1000",
                                          "--history-clamp", "off"], os.path.join(tmp, "ref.png"))
            for spp in a.spp.split(","):
                counts = ["--spp", spp, "--bounce-spp", spp]
                for i, vx in enumerate(a.vx):
                    row = []
                    for denoise in ("off", "on"):
                        errors = [rmse(render(vx, base + counts + ["--denoise", denoise, "--sample-seed", str(s)],
                                              os.path.join(tmp, "frame.png")), ref) for s in (1, 2)]
                        row.append(math.sqrt(sum(e * e for e in errors) / len(errors)))
                    print(f"{name:8s} {spp:>3s} spp  binary {i}: raw {row[0]:.5f}  denoised {row[1]:.5f}  "
                          f"ratio {row[1] / row[0]:.3f}", flush=True)


if __name__ == "__main__":
    main()
