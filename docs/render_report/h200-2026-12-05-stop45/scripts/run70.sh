#!/bin/bash
# Device call 70 (2026-12-05): issue 18's one-frame figures on the seed mirror scene at the final
# code (after stop 44's robustness changes), and Table 6.3's glazed equal-error rows.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
mkdir -p /tmp/dl && tar xzf .devlibs/libs.tgz -C /tmp/dl
export LD_LIBRARY_PATH=/tmp/dl/lib
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
V=.devbuild/vx; chmod +x $V
t0=$(date +%s)
nvidia-smi --query-gpu=name,driver_version,clocks.sm --format=csv
$V info 2>&1 | head -12
M="--scene seed --scene-block mirror --size 1920x1080 --device gpu --reflections 5 --split-hits 5"
mkdir -p /tmp/img
echo "== reference 16/16 x 64 (plain mean), sample seed 1000"
timeout 200 $V render $M --spp 16 --bounce-spp 16 --accumulate 64 --history-clamp off --sample-seed 1000 --out /tmp/img/ref.png 2>&1 | grep -v "^$" | tail -12
echo "elapsed $(( $(date +%s) - t0 )) s"
for seed in 1 2; do
  for cfg in "d4:--spp 4 --bounce-spp 4 --denoise on" "d4c:--spp 4 --bounce-spp 4 --denoise on --light-cache on" "r25:--spp 25 --bounce-spp 25"; do
    name=${cfg%%:*}; args=${cfg#*:}
    echo "== $name seed $seed: $args"
    timeout 120 $V render $M $args --sample-seed $seed --repeat 12 --out /tmp/img/${name}_$seed.png 2>&1 | grep -E "frame 1|frames 2|wrote|error|fail|build|chunks" | head -8
  done
  echo "elapsed $(( $(date +%s) - t0 )) s"
done
python3 - <<'PY'
import numpy as np, glob, os
from PIL import Image
def load(p): return np.asarray(Image.open(p).convert("RGB"), dtype=np.float64) / 255.0
ref = load("/tmp/img/ref.png")
for p in sorted(glob.glob("/tmp/img/*_*.png")):
    print("rmse %-12s %.6f" % (os.path.basename(p), np.sqrt(np.mean((load(p) - ref) ** 2))))
PY
cp /tmp/img/ref.png /tmp/img/d4c_1.png /tmp/img/r25_1.png $OUT/ 2>/dev/null
if [ $(( $(date +%s) - t0 )) -lt 330 ]; then
  echo "== Table 6.3, glazed, thesis lighting, equal error"
  timeout 230 $V bench render --scene seed --scene-block glazed --size 1920x1080 --reference-spp 256 --repeat 10 --device gpu --lighting thesis --sections equal-error --split-hits 5 --out /tmp/eq 2>&1 | tail -30
  cp /tmp/eq/equal_error.csv $OUT/ 2>/dev/null
fi
echo "total: $(( $(date +%s) - t0 )) s"
