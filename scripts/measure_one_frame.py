#!/usr/bin/env python3
"""Issue 18's one-frame target on the hidden-style lavapipe scene: 4 spp denoised against 25 spp raw.

The scene (docs/render_report.md, "Reflected light filtered in the reflected surface's terms"),
written to a temporary raw volume of 48 x 16 x 48 u8: a stone and sand checker floor, a mirror
wall at z 0, four stone pillars and a stone overhang. Two views (overview; along the mirror),
112x72, 4 reflection bounces, default lighting. Reference per view: --spp 8 --accumulate 128
--history-clamp off (1024 samples per pixel, the plain mean) with sample seed 1000, disjoint
from the measured frames' seeds 1-4. Prints, per view and configuration, the root mean square
over the seeds of the RMSE of the 8-bit images (render/image_metrics.h's measure), and each
seed's.

Usage: scripts/measure_one_frame.py VX [OLD_VX]
  (VK_DRIVER_FILES picks the device; OLD_VX: a second binary, e.g. the base commit, measured
  against the same references, made with VX)
"""
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from measure_sampling import Volume, read_png, rmse  # noqa: E402

VIEWS = {"overview": ("42,6,20", "22,2,0"), "along the mirror": ("36,4,3.5", "20,3,0")}
CONFIGS = (("4 spp raw", ["--spp", "4"]), ("4 spp denoised", ["--spp", "4", "--denoise", "on"]),
           ("25 spp raw", ["--spp", "25"]),
           ("4 spp raw, light cache", ["--spp", "4", "--light-cache", "on"]),
           ("4 spp denoised, light cache", ["--spp", "4", "--denoise", "on", "--light-cache", "on"]))
SEEDS = (1, 2, 3, 4)


def checker(x, z):
    """The floor: sand (4) where (x/2 + z/2) is odd, stone (1) elsewhere."""
    return 4 if (x // 2 + z // 2) & 1 else 1


def scene(path):
    xs, ys, zs = 48, 16, 48
    vol = Volume(xs, ys, zs)
    put = vol.put

    vol.fill_layer(0, checker)
    for x in range(xs):
        for y in range(1, 11):
            put(x, y, 0, 7)  # Mirror wall.
    for px, pz in ((10, 10), (20, 8), (30, 12), (38, 6)):
        for y in range(1, 8):
            for dz in range(2):
                for dx in range(2):
                    put(px + dx, y, pz + dz, 1)  # Pillars.
    for x in range(8, 34):
        for z in range(4, 16):
            put(x, 8, z, 1)  # Overhang.
    vol.write(path)


def render(vx, raw, view, out, extra):
    eye, target = VIEWS[view]
    cmd = [vx, "render", "--raw", raw, "--dims", "48,16,48", "--eye", eye, "--target", target,
           "--size", "112x72", "--reflections", "4", "--out", out, *extra]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"vx render failed: {' '.join(cmd)}\n{r.stdout}{r.stderr}")
    return read_png(out)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    binaries = sys.argv[1:3]
    with tempfile.TemporaryDirectory() as tmp:
        raw = os.path.join(tmp, "scene.raw")
        scene(raw)
        png = os.path.join(tmp, "frame.png")
        for view in VIEWS:
            ref = render(binaries[0], raw, view, png, ["--spp", "8", "--accumulate", "128", "--history-clamp", "off",
                                                           "--sample-seed", "1000"])
            for vx in binaries:
                for name, extra in CONFIGS:
                    errors = [rmse(render(vx, raw, view, png, extra + ["--sample-seed", str(s)]), ref) for s in SEEDS]
                    total = math.sqrt(sum(e * e for e in errors) / len(errors))
                    each = " ".join(f"{e:.4f}" for e in errors)
                    print(f"{view}, {name}, {vx}: RMSE {total:.4f} ({each})",
                          flush=True)


if __name__ == "__main__":
    main()
