#!/usr/bin/env bash
# Stop 65's first device call (call 4): the denoiser's a-trous passes (RenderSettings::denoise_passes) on the
# seed mirror scene at 1080p, and the engine's rendering tests now that they honour
# VX_TEST_DEVICE. Run from the repository root on the lent GPU machine with .gl, .devlibs and
# .devbuild carried; .devbuild holds vx, vx_facade_render_tests and vx_engine_render_tests built
# from 2ef107f or later.
source docs/render_report/scripts/device_env.sh
pre=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1)
M="--scene seed --scene-block mirror --size 1920x1080 --device gpu --reflections 5 --split-hits 5"
mkdir -p /tmp/img
echo "== reference 16/16 x 64 (plain mean), sample seed 1000"
timeout 200 $B/vx render $M --spp 16 --bounce-spp 16 --accumulate 64 --history-clamp off --sample-seed 1000 \
  --out /tmp/img/ref.png 2>&1 | grep -E "frame 1|accumulated|wrote|error" | head -4
echo "# at $(( $(date +%s) - t0 )) s"
for seed in 1 2; do
  for cfg in "d4p5:--denoise-passes 5" "d4p3:--denoise-passes 3" "d4p2:--denoise-passes 2" \
             "d4cp5:--light-cache on --denoise-passes 5" "d4cp3:--light-cache on --denoise-passes 3" \
             "d4cp2:--light-cache on --denoise-passes 2"; do
    name=${cfg%%:*}; args=${cfg#*:}
    echo "== $name seed $seed: 4/4 denoised $args"
    timeout 60 $B/vx render $M --spp 4 --bounce-spp 4 --denoise on $args --sample-seed $seed --repeat 12 \
      --out /tmp/img/${name}_$seed.png 2>&1 | grep -E "frames 2|error|fail" | head -3
  done
done
echo "== r25 seed 1: 25/25 raw"
timeout 60 $B/vx render $M --spp 25 --bounce-spp 25 --sample-seed 1 --repeat 12 --out /tmp/img/r25_1.png 2>&1 |
  grep -E "frames 2|error|fail" | head -3
echo "# at $(( $(date +%s) - t0 )) s"
python3 - <<'PY'
import numpy as np, glob, os
from PIL import Image
def load(p): return np.asarray(Image.open(p).convert("RGB"), dtype=np.float64) / 255.0
ref = load("/tmp/img/ref.png")
for p in sorted(glob.glob("/tmp/img/*_*.png")):
    print("rmse %-12s %.6f" % (os.path.basename(p), np.sqrt(np.mean((load(p) - ref) ** 2))))
PY
# (the images stay on the machine: the RMSE lines are what is kept)
for bin in vx_facade_render_tests vx_engine_render_tests; do
  echo "# $bin"
  LD_PRELOAD=$pre VX_TEST_DEVICE=gpu timeout 200 "$B/$bin" 2>&1 |
    grep -E "^\[  (FAILED|PASSED|SKIPPED) |tests ran|Failure|Which is|skip" | head -30
  echo "# at $(( $(date +%s) - t0 )) s"
done
