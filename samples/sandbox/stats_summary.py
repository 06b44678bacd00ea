#!/usr/bin/env python3
"""Summarises a vx_sandbox --stats-out CSV: frame time median and p99 (frames after the first
`--skip` frames), update/render medians, BLAS builds/refits, edit-to-screen frames, and (newer
CSVs) main-thread CPU and levels of detail: frames with holes, coarse chunks drawn.
Usage: stats_summary.py FILE.csv [--skip N]"""
import csv
import sys


def pct(values, p):
    v = sorted(values)
    return v[min(len(v) - 1, int(round(p / 100 * (len(v) - 1))))] if v else float("nan")


def main():
    path = sys.argv[1]
    skip = int(sys.argv[sys.argv.index("--skip") + 1]) if "--skip" in sys.argv else 1
    rows = list(csv.DictReader(open(path)))[skip:]
    ft = [float(r["frame_ms"]) for r in rows]
    up = [float(r["update_ms"]) for r in rows]
    rd = [float(r["render_ms"]) for r in rows]
    e2s = [int(r["edit_to_screen"]) for r in rows if int(r["edit_to_screen"]) >= 0]
    print(f"{path}: {len(rows)} frames; frame ms median {pct(ft, 50):.1f} p99 {pct(ft, 99):.1f}; "
          f"update median {pct(up, 50):.2f} p99 {pct(up, 99):.2f}; render median {pct(rd, 50):.1f}; "
          f"BLAS builds {sum(int(r['builds']) for r in rows)} refits {sum(int(r['refits']) for r in rows)}; "
          f"edits {len(e2s)}, edit-to-screen frames max {max(e2s) if e2s else '-'}")
    if rows and "in_view" in rows[0]:
        holes = [int(r["in_view"]) - int(r["meshed"]) for r in rows]
        print(f"  frames with unmeshed chunks in view: {sum(h > 0 for h in holes)}, most at once: {max(holes)}")
    if rows and "render_cpu_ms" in rows[0]:
        rc = [float(r["render_cpu_ms"]) for r in rows]
        uc = [float(r["update_cpu_ms"]) for r in rows]
        print(f"  CPU: recording a frame median {pct(rc, 50):.3f} p99 {pct(rc, 99):.3f} ms; "
              f"update() median {pct(uc, 50):.3f} p99 {pct(uc, 99):.3f} ms")
    if rows and "holes" in rows[0]:
        holes = [int(r["holes"]) for r in rows]
        coarse = [int(r["coarse_drawn"]) for r in rows]
        print(f"  levels of detail: frames with holes {sum(h > 0 for h in holes)} (most {max(holes)}); "
              f"coarse chunks drawn median {pct(coarse, 50):.0f}")
    if rows and "gpu_mb" in rows[0]:
        print(f"  GPU memory held: max {max(float(r['gpu_mb']) for r in rows):.0f} MiB")


main()
