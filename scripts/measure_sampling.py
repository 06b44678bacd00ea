#!/usr/bin/env python3
"""One-frame error of `vx render` against a converged reference on issue 18's lavapipe scene.

The scene (written to a temporary raw volume, 48 x 24 x 48 u8): a stone floor, four grass
pillars holding a sand overhang 8 blocks up (its soft shadow under the area light), a mirror wall
along one side. The view looks over the floor at the overhang and the wall. Reference: --spp 8
--accumulate 32 --history-clamp off (256 samples per pixel, no filter, the plain mean) with
sample seeds of its own (1000 on), so its noise is independent of the frames measured. Then one
frame at each --spp in SPPS, raw and denoised, and an 8-frame still camera at 4 spp, each with
SEEDS sample seeds; prints the RMSE (over R, G, B of the 8-bit PNGs, as render/image_metrics.h;
the root of the mean square over the seeds), and the same after a 5x5 box filter of both images: how much of the error a spatial
filter could remove (blue-noise error has little left). Both binaries get the same seeds.

Usage: scripts/measure_sampling.py VX [OLD_VX] [--size WxH] [--lighting default|thesis]
  (VK_DRIVER_FILES picks the device; OLD_VX: a second binary measured the same way, e.g. the
  base commit; its reference is its own; VX_KEEP_PNG=DIR copies the images there)
"""
import math
import os
import struct
import subprocess
import sys
import tempfile
import zlib

SPPS = (1, 4, 25)
SEEDS = (1, 2, 3, 4)
EYE, TARGET = "2,14,50", "26,3,20"


class Volume:
    """A raw volume of u8 block ids, x fastest, then y, then z (vx render --raw's layout)."""

    def __init__(self, xs, ys, zs):
        self.xs, self.ys, self.zs = xs, ys, zs
        self.v = bytearray(xs * ys * zs)

    def put(self, x, y, z, b):
        self.v[x + self.xs * (y + self.ys * z)] = b

    def fill_layer(self, y, block_at):
        """Layer y: block_at(x, z) at every column."""
        for z in range(self.zs):
            for x in range(self.xs):
                self.put(x, y, z, block_at(x, z))

    def write(self, path):
        with open(path, "wb") as f:
            f.write(self.v)


def scene(path):
    xs, ys, zs = 48, 24, 48
    vol = Volume(xs, ys, zs)
    put = vol.put
    vol.fill_layer(0, lambda x, z: 1)  # Stone floor.
    for px, pz in ((10, 10), (10, 26), (28, 10), (28, 26)):
        for y in range(1, 8):
            for dz in range(2):
                for dx in range(2):
                    put(px + dx, y, pz + dz, 3)  # Grass pillars.
    for z in range(8, 30):
        for x in range(8, 32):
            put(x, 8, z, 4)  # Sand overhang.
    for z in range(2, 46):
        for y in range(1, 14):
            put(40, y, z, 7)  # Mirror wall.
    vol.write(path)


def read_png(path):
    """8-bit RGB or RGBA PNG (non-interlaced) to a flat list of floats in [0, 1], RGB only."""
    with open(path, "rb") as f:
        data = f.read()
    pos, idat, w, h, ctype = 8, b"", 0, 0, 6
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and ctype in (2, 6), "8-bit RGB(A) only"
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    bpp = 4 if ctype == 6 else 3
    raw, stride = zlib.decompress(idat), w * bpp
    out, prev = [], bytearray(stride)
    for y in range(h):
        ft, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if ft == 1:
                line[i] = (line[i] + a) & 255
            elif ft == 2:
                line[i] = (line[i] + b) & 255
            elif ft == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif ft == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        for i in range(0, stride, bpp):
            out.extend(line[i:i + 3])
        prev = line
    return [x / 255.0 for x in out]


def rmse(a, b):
    return math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b)) / len(a))


def box5(img, w, h):
    """5x5 box filter of an RGB image (window cut at the borders)."""
    out = [0.0] * len(img)
    for y in range(h):
        for x in range(w):
            ys, xs = range(max(y - 2, 0), min(y + 3, h)), range(max(x - 2, 0), min(x + 3, w))
            n = len(ys) * len(xs)
            for c in range(3):
                out[(y * w + x) * 3 + c] = sum(img[(yy * w + xx) * 3 + c] for yy in ys for xx in xs) / n
    return out


def render(vx, raw, size, lighting, out, extra):
    cmd = [vx, "render", "--raw", raw, "--dims", "48,24,48", "--eye", EYE, "--target", TARGET,
           "--size", size, "--out", out, *extra]
    if lighting != "default":
        cmd += ["--lighting", lighting]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"vx render failed: {' '.join(cmd)}\n{r.stdout}{r.stderr}")
    return read_png(out)


def measure(name, vx, raw, size, lighting, tmp):
    w, h = (int(v) for v in size.split("x"))
    ref = render(vx, raw, size, lighting, os.path.join(tmp, f"{name}_ref.png"),
                 ["--spp", "8", "--accumulate", "32", "--history-clamp", "off", "--sample-seed", "1000"])
    ref_box = box5(ref, w, h)

    def error(label, extra):
        sq = sq_box = 0.0
        for seed in SEEDS:
            img = render(vx, raw, size, lighting, os.path.join(tmp, f"{name}_{label}_{seed}.png"),
                         extra + ["--sample-seed", str(seed * 100)])
            sq += rmse(img, ref) ** 2
            sq_box += rmse(box5(img, w, h), ref_box) ** 2
        return math.sqrt(sq / len(SEEDS)), math.sqrt(sq_box / len(SEEDS))

    rows = []
    for spp in SPPS:
        for denoise in ("off", "on"):
            rows.append((f"{spp} spp, 1 frame, denoiser {denoise}",
                         error(f"{spp}_{denoise}", ["--spp", str(spp), "--denoise", denoise])))
    for denoise in ("off", "on"):
        rows.append((f"4 spp, still camera 8 frames, denoiser {denoise}",
                     error(f"acc_{denoise}", ["--spp", "4", "--accumulate", "8", "--denoise", denoise])))
    return rows


def main():
    args = sys.argv[1:]
    size, lighting = "112x72", "default"
    if "--size" in args:
        i = args.index("--size"); size = args[i + 1]; del args[i:i + 2]
    if "--lighting" in args:
        i = args.index("--lighting"); lighting = args[i + 1]; del args[i:i + 2]
    if not args:
        sys.exit(__doc__)
    names = ["new", "old"][:len(args)]
    with tempfile.TemporaryDirectory() as tmp:
        raw = os.path.join(tmp, "scene.raw")
        scene(raw)
        results = {n: measure(n, vx, raw, size, lighting, tmp) for n, vx in zip(names, args)}
        if os.environ.get("VX_KEEP_PNG"):
            subprocess.run(["cp", "-r", tmp, os.environ["VX_KEEP_PNG"]])
    header = ("| configuration | " + " | ".join(f"RMSE {n}" for n in names) + " | " +
              " | ".join(f"5x5 box RMSE {n}" for n in names) + " |")
    print(header)
    print("|---" * (2 * len(names) + 1) + "|")
    for i, (row, _) in enumerate(results["new"]):
        cells = " | ".join(f"{results[n][i][1][0]:.4f}" for n in names)
        boxed = " | ".join(f"{results[n][i][1][1]:.4f}" for n in names)
        print(f"| {row} | {cells} | {boxed} |")


if __name__ == "__main__":
    main()
