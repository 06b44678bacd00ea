#!/usr/bin/env python3
"""Trace time of each lighting term (issue 10), measured with `vx render` on lavapipe or a GPU.

Writes the `hills` raw volume (96 x 32 x 96 u8: stone, grass on top at 8 + 5 sin 0.15x +
4 cos 0.11z) to a temporary file, then runs each configuration ROUNDS times, interleaved (a busy
machine drifts: interleaving spreads the drift over all of them), and prints for each the median
over rounds of `vx render --repeat 6`'s median trace time (GPU timestamps, frames 2..6).

Usage: scripts/bench_lighting.py VX [OLD_VX] [--size WxH] [--rounds N] [--seed-terrain]
  (VK_DRIVER_FILES picks the device; OLD_VX: a second binary run interleaved, e.g. the base commit,
  for the configurations it understands; --seed-terrain: generated terrain instead of hills)
"""
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile

CONFIGS = [
    ("flat", ["--shading", "flat"], True),
    ("area light only (the old Full)", ["--sun", "off", "--sky-light", "0"], True),
    ("nothing lit", ["--sun", "off", "--sky-light", "0", "--area-light", "off"], False),
    ("sealed off from the sky", ["--area-light", "off", "--sky-access", "off"], False),
    ("sun only", ["--area-light", "off", "--sky-light", "0"], False),
    ("sky term only", ["--area-light", "off", "--sun", "off"], False),
    ("sun + sky", ["--area-light", "off"], False),
    ("everything (default)", [], False),
]


def hills(path):
    x_size, y_size, z_size = 96, 32, 96
    data = bytearray(x_size * y_size * z_size)
    for z in range(z_size):
        for x in range(x_size):
            h = 8 + int(5 * math.sin(x * 0.15) + 4 * math.cos(z * 0.11))
            for y in range(h):
                data[x + x_size * (y + y_size * z)] = 3 if y == h - 1 else 1
    with open(path, "wb") as f:
        f.write(data)


def trace_ms(vx, scene, size, extra):
    out = subprocess.run([vx, "render", *scene, "--size", size, "--spp", "4", "--repeat", "6",
                          "--out", os.path.join(tempfile.gettempdir(), "bench_lighting.png"),
                          *extra], capture_output=True, text=True)
    m = re.search(r"frames 2\.\.\d+ .*?trace ([0-9.]+) ms", out.stdout)
    if not m:
        sys.exit(f"vx render failed: {out.stdout}{out.stderr}")
    return float(m.group(1))


def main():
    args = sys.argv[1:]
    size, rounds, terrain = "320x180", 3, False
    if "--size" in args:
        i = args.index("--size"); size = args[i + 1]; del args[i:i + 2]
    if "--rounds" in args:
        i = args.index("--rounds"); rounds = int(args[i + 1]); del args[i:i + 2]
    if "--seed-terrain" in args:
        args.remove("--seed-terrain"); terrain = True
    if not args:
        sys.exit(__doc__)
    binaries = {"new": args[0]}
    if len(args) > 1:
        binaries["old"] = args[1]
    with tempfile.TemporaryDirectory() as tmp:
        if terrain:
            scene = ["--seed", "7", "--radius", "2", "--vradius", "2"]
        else:
            raw = os.path.join(tmp, "hills.raw")
            hills(raw)
            scene = ["--raw", raw, "--dims", "96,32,96"]
        times = {}
        for _ in range(rounds):
            for name, extra, old_too in CONFIGS:
                for which, vx in binaries.items():
                    if which == "old" and not old_too:
                        continue
                    # The old binary knows none of the new options: its Full is the area light only.
                    opts = [] if which == "old" and extra[:1] != ["--shading"] else extra
                    times.setdefault((name, which), []).append(trace_ms(vx, scene, size, opts))
        for name, _, _ in CONFIGS:
            row = [f"{which} {statistics.median(times[(name, which)]):.1f} ms"
                   for which in binaries if (name, which) in times]
            print(f"{name}: " + ", ".join(row))


if __name__ == "__main__":
    main()
