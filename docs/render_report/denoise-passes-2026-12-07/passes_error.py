"""Stop 65's error table: issue 18's hidden-style scene (scripts/measure_one_frame.py: both views,
4 sample seeds against an 8 spp x 128-frame plain mean), 4 spp denoised at several settings.

Usage (from the repository root): python3 docs/render_report/denoise-passes-2026-12-07/passes_error.py
    REF_VX 'label=VX:extra args' ...
Each item renders `--spp 4 --denoise on` plus its extra arguments, e.g.
    'cache p3=build/release/tools/vx:--light-cache on --denoise-passes 3'
"""
import math
import os
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "scripts"))
import measure_one_frame as m  # noqa: E402


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    runs = []
    for item in sys.argv[2:]:
        label, rest = item.split("=", 1)
        vx, _, extra = rest.partition(":")
        runs.append((label, vx, extra.split()))
    with tempfile.TemporaryDirectory() as tmp:
        raw = os.path.join(tmp, "scene.raw")
        m.scene(raw)
        png = os.path.join(tmp, "frame.png")
        for view in m.VIEWS:
            ref = m.render(sys.argv[1], raw, view, png,
                           ["--spp", "8", "--accumulate", "128", "--history-clamp", "off", "--sample-seed", "1000"])
            for label, vx, extra in runs:
                args = ["--spp", "4", "--denoise", "on"] + extra
                errors = [m.rmse(m.render(vx, raw, view, png, args + ["--sample-seed", str(s)]), ref) for s in m.SEEDS]
                total = math.sqrt(sum(e * e for e in errors) / len(errors))
                print(f"{view}, {label}: RMSE {total:.5f} (" + " ".join(f"{e:.4f}" for e in errors) + ")", flush=True)


if __name__ == "__main__":
    main()
