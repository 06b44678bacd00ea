#!/usr/bin/env python3
"""Where a one-frame image's error comes from: by light and by reflection depth (issue 18).

Renders a view with `vx render` in groups: every light at the full reflection depth; every light
at depths 0, 1 and 2; then each light alone (sun, sky light, area light) at the full depth. Per
group: a plain-mean reference (8 spp x 64 frames, sample seed 9000, disjoint from the measured
frames' seeds), then one frame of 25 spp raw (the thesis-style frame) and of 4 spp raw / denoised,
with and without the light cache, each against it. Prints per configuration the RMSE of the
8-bit images (render/image_metrics.h's), the share of the squared error held by the worst 10% of
pixels, and per group the reference's own variation over 3x3 pixels: the RMSE between the
reference and its 3x3 box filter, which is what averaging with the eight neighbours would cost a
noise-free image (a floor for any filter that shares light between pixels without knowing which
pixels see the same surface).

Scenes: `hidden` (default), measure_one_frame.py's floor, pillars, overhang and mirror wall,
112x72, 4 reflections, its overview; `seed-mirror`, the thesis's seed scene of mirror blocks
(`--scene seed --scene-block mirror`), 5 reflections, the default view, --size (default
1920x1080: a GPU's job; lavapipe needs minutes per frame at that size).

Usage: scripts/measure_error_sources.py VX [--scene hidden|seed-mirror] [--size WxH]
                                            [--device D] [--seeds N]
  (numpy is used when installed: 1080p frames need it; small ones do without)
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from measure_one_frame import VIEWS, scene  # noqa: E402
from measure_sampling import read_png  # noqa: E402

try:
    import numpy as np
except ImportError:  # Small images only.
    np = None

CONFIGS = (("25 spp raw", ["--spp", "25"]), ("4 spp raw", ["--spp", "4"]),
           ("4 spp raw, cache", ["--spp", "4", "--light-cache", "on"]),
           ("4 spp denoised", ["--spp", "4", "--denoise", "on"]),
           ("4 spp denoised, cache", ["--spp", "4", "--denoise", "on", "--light-cache", "on"]))
REFERENCE = ["--spp", "8", "--accumulate", "64", "--history-clamp", "off", "--sample-seed", "9000"]


def groups(depth):
    return (("all lights", ["--reflections", str(depth)]), ("all lights, depth 0", ["--reflections", "0"]),
            ("all lights, depth 1", ["--reflections", "1"]), ("all lights, depth 2", ["--reflections", "2"]),
            ("sun alone", ["--reflections", str(depth), "--sky-light", "0", "--area-light", "off"]),
            ("sky light alone", ["--reflections", str(depth), "--sun", "off", "--area-light", "off"]),
            ("area light alone", ["--reflections", str(depth), "--sun", "off", "--sky-light", "0"]))


class Image:
    """An RGB image in [0, 1]: a numpy array (h, w, 3) or a flat list."""

    def __init__(self, path, w, h):
        self.w, self.h = w, h
        self.px = read_png_array(path, w, h) if np is not None else read_png(path)

    def errors(self, ref):
        """Per-pixel squared error, the mean over RGB."""
        if np is not None:
            return ((self.px - ref.px) ** 2).mean(axis=2).ravel()
        a, b = self.px, ref.px
        return [sum((a[i + c] - b[i + c]) ** 2 for c in range(3)) / 3 for i in range(0, len(a), 3)]

    def box3(self):
        out = Image.__new__(Image)
        out.w, out.h = self.w, self.h
        if np is not None:
            pad = np.pad(self.px, ((1, 1), (1, 1), (0, 0)), mode="edge")
            out.px = sum(pad[dy:dy + self.h, dx:dx + self.w] for dy in range(3) for dx in range(3)) / 9.0
            return out
        w, h, img, res = self.w, self.h, self.px, [0.0] * len(self.px)
        for y in range(h):
            for x in range(w):
                for c in range(3):
                    res[(y * w + x) * 3 + c] = sum(img[(min(max(y + dy, 0), h - 1) * w + min(max(x + dx, 0), w - 1)) * 3 + c]
                                                   for dy in (-1, 0, 1) for dx in (-1, 0, 1)) / 9.0
        out.px = res
        return out


def read_png_array(path, w, h):
    """A w x h 8-bit PNG as a numpy array (h, w, 3): Pillow's decoder when installed, else the pure reader."""
    try:
        from PIL import Image as PilImage
        return np.asarray(PilImage.open(path).convert("RGB"), dtype=np.float64) / 255.0
    except ImportError:
        return np.asarray(read_png(path), dtype=np.float64).reshape(h, w, 3)


def summary(err):
    """RMSE, and the share of the squared error held by the worst tenth of the pixels."""
    total = float(sum(err))
    worst = sorted(err, reverse=True)[:max(1, len(err) // 10)] if np is None else np.sort(err)[::-1][:max(1, len(err) // 10)]
    return math.sqrt(total / len(err)), (float(sum(worst)) / total if total > 0 else 0.0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("vx")
    ap.add_argument("--scene", choices=("hidden", "seed-mirror"), default="hidden")
    ap.add_argument("--size", default=None)
    ap.add_argument("--device", default=None)
    ap.add_argument("--seeds", type=int, default=1)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        if a.scene == "hidden":
            raw = os.path.join(tmp, "scene.raw")
            scene(raw)
            eye, target = VIEWS["overview"]
            base = ["--raw", raw, "--dims", "48,16,48", "--eye", eye, "--target", target]
            size, depth = a.size or "112x72", 4
        else:
            base = ["--scene", "seed", "--scene-block", "mirror"]
            size, depth = a.size or "1920x1080", 5
        base += ["--size", size] + (["--device", a.device] if a.device else [])
        w, h = (int(v) for v in size.split("x"))
        png = os.path.join(tmp, "frame.png")

        def frame(extra):
            cmd = [a.vx, "render", *base, *extra, "--out", png]
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode != 0:
                sys.exit(f"vx render failed: {' '.join(cmd)}\n{r.stdout}{r.stderr}")
            return Image(png, w, h)

        print(f"scene {a.scene}, {size}, {a.seeds} seed(s); RMSE of 8-bit images, root mean square over seeds")
        for name, extra in groups(depth):
            ref = frame(extra + REFERENCE)
            own, _ = summary(ref.box3().errors(ref))
            print(f"\n{name}: the reference's own 3x3 variation {own:.5f}", flush=True)
            for label, cfg in CONFIGS:
                runs = [summary(frame(extra + cfg + ["--sample-seed", str(s)]).errors(ref)) for s in range(1, a.seeds + 1)]
                e = math.sqrt(sum(r[0] ** 2 for r in runs) / len(runs))
                worst = sum(r[1] for r in runs) / len(runs)
                print(f"  {label:24s} RMSE {e:.5f}   worst 10% of pixels: {100 * worst:.0f}% of the squared error",
                      flush=True)


if __name__ == "__main__":
    main()
