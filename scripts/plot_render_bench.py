#!/usr/bin/python3
"""Error against frame time from `vx bench render`'s CSV: one PNG per metric next to the CSV.

Usage: scripts/plot_render_bench.py DIR/render_bench.csv  (Debian python3: /usr/bin/python3)
Needs python3-matplotlib (scripts/setup.sh installs it).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main() -> int:
    if len(sys.argv) != 2:
        print("usage: plot_render_bench.py render_bench.csv", file=sys.stderr)
        return 2
    path = sys.argv[1]
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        print(f"plot_render_bench.py: no rows in {path}", file=sys.stderr)
        return 1
    out_dir = os.path.dirname(os.path.abspath(path))
    for metric, label in (("rmse", "RMSE"), ("psnr", "PSNR (dB)"), ("ssim", "SSIM")):
        fig, ax = plt.subplots(figsize=(6, 4))
        for denoise, bounce_all, marker in ((0, False, "o"), (0, True, "s"), (1, False, "^"), (1, True, "D")):
            pts = [r for r in rows if int(r["denoise"]) == denoise and
                   (int(r["bounce_spp"]) == int(r["spp"])) == bounce_all]
            pts.sort(key=lambda r: int(r["spp"]))
            if not pts:
                continue
            xs = [float(r["frame_ms"]) for r in pts]
            ys = [float(r[metric]) for r in pts]
            name = ("denoised" if denoise else "raw") + (", bounce spp = spp" if bounce_all else ", bounce spp 1")
            ax.plot(xs, ys, marker=marker, label=name)
            for r, x, y in zip(pts, xs, ys):
                ax.annotate(r["spp"], (x, y), fontsize=7, xytext=(3, 3), textcoords="offset points")
        ax.set_xscale("log")
        if metric == "rmse":
            ax.set_yscale("log")
        ax.set_xlabel("GPU frame time (ms, median)")
        ax.set_ylabel(label + " against the reference")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        png = os.path.join(out_dir, f"error_vs_time_{metric}.png")
        fig.savefig(png, dpi=120)
        plt.close(fig)
        print(f"wrote {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
