#!/usr/bin/env python3
"""Emissive blocks: faces sampled (next-event estimation) against sky rays that hit them by chance.

The scene, written to a temporary raw volume of 48 x 12 x 48 u8: a closed hall (stone and sand
checker floor, stone walls and ceiling, four pillars) lit only by lamps: four single lamp blocks
and a strip of six under the ceiling (27 greedy quads: more than the 8 candidates a sample draws). No
sun, no sky light, no area light, no reflections; exposure EV 9. Reference: the faces sampled,
--spp 16 --accumulate 64 --history-clamp off (1024 samples per pixel, the plain mean) with sample
seed 1000. Per configuration (emitter sampling on / off; spp; raw / denoised): the root mean
square over seeds 1-4 of the RMSE of the 8-bit images against it (render/image_metrics.h's
measure) and the median trace time of frames 2..N of seed 1's --repeat N run.

Usage: scripts/measure_emitters.py VX [--size WxH] [--device D] [--repeat N] [--keep DIR]
"""
import argparse
import math
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from measure_one_frame import checker  # noqa: E402
from measure_sampling import Volume, read_png, rmse  # noqa: E402

SEEDS = (1, 2, 3, 4)
LAMPS = ((15, 1, 15), (26, 3, 12), (34, 1, 30), (12, 6, 30))


def hall(path):
    xs, ys, zs = 48, 12, 48
    vol = Volume(xs, ys, zs)
    put = vol.put

    vol.fill_layer(0, checker)  # measure_one_frame's floor.
    vol.fill_layer(11, lambda x, z: 1)  # Stone ceiling.
    for i in range(48):
        for y in range(12):
            for x, z in ((i, 0), (i, 47), (0, i), (47, i)):
                put(x, y, z, 1)  # Walls.
    for px, pz in ((10, 10), (20, 28), (30, 12), (38, 36)):
        for y in range(1, 11):
            for dz in range(2):
                for dx in range(2):
                    put(px + dx, y, pz + dz, 1)  # Pillars.
    for x, y, z in LAMPS:
        put(x, y, z, 8)  # Lamp.
    for x in range(20, 26):
        put(x, 10, 40, 8)  # A strip of lamps under the ceiling.
    vol.write(path)


def render(vx, raw, a, out, extra):
    cmd = [vx, "render", "--raw", raw, "--dims", "48,12,48", "--eye", "44,7,44", "--target", "20,1,16",
           "--size", a.size, "--sun", "off", "--sky-light", "0", "--area-light", "off", "--reflections", "0",
           "--exposure", "9", "--device", a.device, "--out", out, *extra]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{r.stdout}{r.stderr}")
    m = re.search(r"frames 2\.\.\d+ \(medians of \d+\):.*?trace ([0-9.]+) ms", r.stdout)
    return read_png(out), float(m.group(1)) if m else float("nan")


def main():
    p = argparse.ArgumentParser()
    p.add_argument("vx")
    p.add_argument("--size", default="160x90")
    p.add_argument("--device", default="auto")
    p.add_argument("--repeat", type=int, default=7)
    p.add_argument("--keep", help="directory for the PNGs (default: a temporary one)")
    a = p.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        d = a.keep or tmp
        os.makedirs(d, exist_ok=True)
        raw = os.path.join(d, "hall.raw")
        hall(raw)
        ref, _ = render(a.vx, raw, a, os.path.join(d, "ref.png"),
                        ["--spp", "16", "--accumulate", "64", "--history-clamp", "off", "--sample-seed", "1000"])
        print(f"hall {a.size}: RMSE against 1024 spp (faces sampled), trace ms median of frames 2..{a.repeat}")
        print("| emitters | spp | denoiser | trace ms | RMSE |\n|---|---|---|---|---|")
        for spp in (1, 4, 16):
            for denoise in ("off", "on"):
                for faces in ("on", "off"):
                    errors, ms = [], float("nan")
                    for s in SEEDS:
                        extra = ["--spp", str(spp), "--denoise", denoise, "--emitter-sampling", faces,
                                 "--sample-seed", str(s)]
                        if s == SEEDS[0]:
                            extra += ["--repeat", str(a.repeat)]
                        img, t = render(a.vx, raw, a, os.path.join(d, f"{faces}_{spp}_{denoise}_{s}.png"), extra)
                        ms = t if s == SEEDS[0] else ms
                        errors.append(rmse(img, ref))
                    e = math.sqrt(sum(x * x for x in errors) / len(errors))
                    name = "faces sampled" if faces == "on" else "sky rays"
                    print(f"| {name} | {spp} | {denoise} | {ms:.1f} | {e:.4f} |", flush=True)


if __name__ == "__main__":
    main()
