#!/usr/bin/env bash
# Stop 65's second device call (call 5): the light cache with split hits (they now combine) on the seed
# mirror scene at 1080p, against the cache in one pass (--split-hits 0, what the cache forced
# before), and the render tests of the split and the cache on the NVIDIA driver. Run from the
# repository root on the lent GPU machine with .gl, .devlibs and .devbuild carried; .devbuild
# holds vx and vx_render_tests built from this stop's code.
source docs/render_report/scripts/device_env.sh
pre=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1)
M="--scene seed --scene-block mirror --size 1920x1080 --device gpu --reflections 5"
mkdir -p /tmp/img
echo "== reference 16/16 x 64 (plain mean), sample seed 1000"
timeout 200 $B/vx render $M --spp 16 --bounce-spp 16 --accumulate 64 --history-clamp off --sample-seed 1000 \
  --out /tmp/img/ref.png 2>&1 | grep -E "frame 1|accumulated|wrote|error" | head -4
echo "# at $(( $(date +%s) - t0 )) s"
for round in 1 2; do
  for cfg in "cache_split5:--light-cache on --split-hits 5" "cache_split0:--light-cache on --split-hits 0" \
             "split5:--split-hits 5"; do
    name=${cfg%%:*}; args=${cfg#*:}
    echo "== $name round $round: 4/4 denoised, 2 passes, $args"
    timeout 60 $B/vx render $M --spp 4 --bounce-spp 4 --denoise on --denoise-passes 2 $args --sample-seed $round \
      --repeat 12 --out /tmp/img/${name}_$round.png 2>&1 | grep -E "frames 2|error|fail" | head -3
  done
  echo "== r25 round $round: 25/25 raw --split-hits 5"
  timeout 60 $B/vx render $M --spp 25 --bounce-spp 25 --split-hits 5 --sample-seed $round --repeat 12 \
    --out /tmp/img/r25_$round.png 2>&1 | grep -E "frames 2|error|fail" | head -3
done
echo "# at $(( $(date +%s) - t0 )) s"
python3 - <<'PY'
import numpy as np, glob, os
from PIL import Image
def load(p): return np.asarray(Image.open(p).convert("RGB"), dtype=np.float64) / 255.0
ref = load("/tmp/img/ref.png")
for p in sorted(glob.glob("/tmp/img/*_*.png")):
    print("rmse %-18s %.6f" % (os.path.basename(p), np.sqrt(np.mean((load(p) - ref) ** 2))))
a, b = load("/tmp/img/cache_split5_1.png"), load("/tmp/img/cache_split0_1.png")
d = np.abs(a - b) * 255
print("cache split 5 against split 0, seed 1: %d of %d channels differ, worst %.0f steps" % ((d > 0.5).sum(), d.size, d.max()))
PY
echo "# vx_render_tests (split hits, light cache)"
LD_PRELOAD=$pre VX_TEST_DEVICE=gpu timeout 250 "$B/vx_render_tests" --gtest_filter='*SplitHits*:*LightCache*:*SharedLight*:*FullTable*:*Denoiser*' 2>&1 |
  grep -E "^\[  (FAILED|PASSED|SKIPPED) |^\[       OK|channels differ|Failure|Which is|skip" | head -60
echo "# at $(( $(date +%s) - t0 )) s"
