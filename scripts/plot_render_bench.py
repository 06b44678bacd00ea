#!/usr/bin/python3
"""Error against frame time from `vx bench render`'s CSV: one PNG per metric next to the CSV.

Usage: scripts/plot_render_bench.py DIR/render_bench.csv  (Debian python3: /usr/bin/python3)
       scripts/plot_render_bench.py DIR/equal_error.csv   (--sections equal-error: one PNG per
       feature set, RMSE against frame time as a multiple of RT flat, with the target RMSE and the
       thesis's ratios marked)
       scripts/plot_render_bench.py DIR/defaults.csv      (--sections defaults: moving-camera
       error against GPU ms, qualifying candidates filled, the pick starred)
       scripts/plot_render_bench.py DIR/paths.csv         (--sections paths: per-frame RMSE along
       each camera path, the edited pixels' on the edit path dashed)
Needs python3-matplotlib (scripts/setup.sh installs it).
"""
import csv
import itertools
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def finish(fig, ax, png: str) -> str:
    """Grid, legend and layout, then writes the figure to png and closes it; returns png."""
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    plt.close(fig)
    return png


# The thesis's Table 6.3 ratios (RTX 2080 Ti, over its all-off row) per feature set of
# equal_error.csv, as tools/bench_render_equal_error.cpp prints them.
THESIS_RATIOS = {
    "shadows": (("shadows", 8.14),),
    "shadows+reflections": (("shadows + reflections", 19.12), ("all on", 34.82)),
}


def plot_equal_error(rows, out_dir):
    for name in sorted({r["feature_set"] for r in rows}):
        pts = [r for r in rows if r["feature_set"] == name]
        flat = float(pts[0]["flat_ms"])
        fig, ax = plt.subplots(figsize=(6, 4))
        # Samples by weight: exponent 1 ("w") and below 1 (stop 30's weight^0.8: "w^0.8").
        for denoise, cache, weight, exponent, marker in (
                (0, 0, 0, 1, "o"), (1, 0, 0, 1, "^"), (0, 1, 0, 1, "s"), (1, 1, 0, 1, "D"),
                (0, 0, 1, 1, "P"), (1, 0, 1, 1, "X"), (0, 0, 1, 0.8, "*"), (1, 0, 1, 0.8, "v")):
            sel = [r for r in pts if int(r["denoise"]) == denoise and int(r.get("light_cache", 0)) == cache
                   and int(r.get("by_weight", 0)) == weight
                   and abs(float(r.get("weight_exponent", 1)) - exponent) < 1e-6]
            if not sel:
                continue
            xs = [float(r["frame_ms"]) / flat for r in sel]
            ys = [float(r["rmse"]) for r in sel]
            power = "" if exponent == 1 else f"^{exponent:g}"
            ax.scatter(xs, ys, marker=marker,
                       label=("denoised" if denoise else "raw") + (", light cache" if cache else "")
                       + (f", samples by weight{power}" if weight else ""))
            for r, x, y in zip(sel, xs, ys):
                tag = r["spp"] + ("/" + r["bounce_spp"] if int(r["bounce_spp"]) else "") + ("w" + power if weight else "")
                ax.annotate(tag, (x, y), fontsize=6, xytext=(3, 3), textcoords="offset points")
        ax.axhline(float(pts[0]["target_rmse"]), color="k", linestyle="--", linewidth=0.8,
                   label="target: 25 spp raw")
        for label, ratio in THESIS_RATIOS.get(name, ()):
            ax.axvline(ratio, color="r", linestyle=":", linewidth=0.8)
            ax.annotate(f"thesis {label} {ratio}x", (ratio, ax.get_ylim()[1]), fontsize=6, rotation=90,
                        va="top", ha="right", color="r")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("GPU frame time / RT flat frame time")
        ax.set_ylabel("one-frame RMSE against the reference")
        ax.set_title(name, fontsize=9)
        png = os.path.join(out_dir, "equal_error_" + name.replace("+", "_") + ".png")
        print(f"wrote {finish(fig, ax, png)}")


def plot_defaults(rows, out_dir: str) -> str:
    """defaults.csv: error (the larger p95 of the two moving paths) against ms, one PNG."""
    fig, ax = plt.subplots(figsize=(6, 4))
    for denoise, marker, name in ((0, "o", "denoiser off"), (1, "^", "denoiser on")):
        pts = [r for r in rows if int(r["denoise"]) == denoise]
        for qualifies, fill in ((1, "full"), (0, "none")):
            sel = [r for r in pts if int(r["qualifies"]) == qualifies]
            if sel:
                ax.plot([float(r["ms"]) for r in sel], [float(r["error"]) for r in sel], marker=marker,
                        linestyle="", fillstyle=fill, color="C%d" % denoise,
                        label=name + (", qualifies" if qualifies else ""))
    for r in rows:
        label = r["shadow_spp"] + "/" + r["bounce_spp"] + (" h" + r["history"] if int(r["denoise"]) else "")
        label += " (now)" if int(r["sandbox_now"]) else ""
        ax.annotate(label, (float(r["ms"]), float(r["error"])), fontsize=7, xytext=(3, 3),
                    textcoords="offset points")
        if int(r["pick"]):
            ax.plot([float(r["ms"])], [float(r["error"])], marker="*", markersize=14, linestyle="",
                    color="C3", label="the pick")
    ax.set_xscale("log")
    ax.set_xlabel("GPU ms per frame (trace + denoiser, median)")
    ax.set_ylabel("moving-camera RMSE p95 (worse path)")
    return finish(fig, ax, os.path.join(out_dir, "defaults_error_vs_ms.png"))


def plot_paths(rows, out_dir: str) -> str:
    """paths.csv: per-frame RMSE along each camera path, one panel per path, one line per
    configuration; on the edit path also the edited pixels' RMSE (dashed)."""
    paths = list(dict.fromkeys(r["path"] for r in rows))
    fig, axes = plt.subplots(1, len(paths), figsize=(5 * len(paths), 4), squeeze=False)
    for ax, name in zip(axes[0], paths):
        configs = list(dict.fromkeys(r["configuration"] for r in rows if r["path"] == name))
        for i, config in enumerate(configs):
            sel = [r for r in rows if r["path"] == name and r["configuration"] == config]
            frames = [int(r["frame"]) for r in sel]
            ax.plot(frames, [float(r["rmse"]) for r in sel], color="C%d" % i, label=config)
            edited = [float(r["edited_rmse"]) for r in sel]
            if min(edited) >= 0.0:
                ax.plot(frames, edited, color="C%d" % i, linestyle="--", linewidth=0.8)
        ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.3)
        ax.set_xlabel("frame")
        ax.set_ylabel("RMSE against the reference at the pose")
        ax.set_title(name + (" (dashed: the edited pixels)" if name == "edit" else ""), fontsize=9)
    return finish(fig, axes[0][-1], os.path.join(out_dir, "paths_rmse_per_frame.png"))


def main() -> int:
    if len(sys.argv) != 2:
        print("usage: plot_render_bench.py render_bench.csv|equal_error.csv|defaults.csv|paths.csv",
              file=sys.stderr)
        return 2
    path = sys.argv[1]
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        print(f"plot_render_bench.py: no rows in {path}", file=sys.stderr)
        return 1
    out_dir = os.path.dirname(os.path.abspath(path))
    if "edited_rmse" in rows[0]:
        print(f"wrote {plot_paths(rows, out_dir)}")
        return 0
    if "feature_set" in rows[0]:
        plot_equal_error(rows, out_dir)
        return 0
    if "best_at_2x" in rows[0]:
        print(f"wrote {plot_defaults(rows, out_dir)}")
        return 0
    for metric, label in (("rmse", "RMSE"), ("psnr", "PSNR (dB)"), ("ssim", "SSIM")):
        fig, ax = plt.subplots(figsize=(6, 4))
        for (denoise, bounce_all, marker), cache in itertools.product(
                ((0, False, "o"), (0, True, "s"), (1, False, "^"), (1, True, "D")), (0, 1)):
            pts = [r for r in rows if int(r["denoise"]) == denoise and int(r.get("light_cache", 0)) == cache and
                   (int(r["bounce_spp"]) == int(r["spp"])) == bounce_all]
            pts.sort(key=lambda r: int(r["spp"]))
            if not pts:
                continue
            xs = [float(r["frame_ms"]) for r in pts]
            ys = [float(r[metric]) for r in pts]
            name = ("denoised" if denoise else "raw") + (", bounce spp = spp" if bounce_all else ", bounce spp 1")
            name += ", light cache" if cache else ""
            ax.plot(xs, ys, marker=marker, linestyle="--" if cache else "-", label=name)
            for r, x, y in zip(pts, xs, ys):
                ax.annotate(r["spp"], (x, y), fontsize=7, xytext=(3, 3), textcoords="offset points")
        ax.set_xscale("log")
        if metric == "rmse":
            ax.set_yscale("log")
        ax.set_xlabel("GPU frame time (ms, median)")
        ax.set_ylabel(label + " against the reference")
        print(f"wrote {finish(fig, ax, os.path.join(out_dir, f'error_vs_time_{metric}.png'))}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
