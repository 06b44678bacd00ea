#!/usr/bin/env bash
# Issue 18's GPU half on the seed mirror scene at 1080p, before (.devbuild/vx_base) and after
# (.devbuild/vx) a stop's renderer changes: the one-frame RMSE of 4 / 4 denoised with the light
# cache, 2 passes, split hits 5, and its frame time against 25 / 25 raw interleaved in one process
# (`vx render --versus-raw 25`); then the denoiser and light cache render tests on the NVIDIA
# driver. Run from the repository root on the lent GPU machine with .gl, .devlibs and .devbuild
# carried. Stop 67: vx_base 52bfe1a, vx 5ad3f18 (16 x 16 groups, no output store under the
# denoiser, the footprint over 3 x 3 pixels 2 apart). Stop 68: vx_base d87f019, vx a18014f (raw
# frames' primary sky rays as occlusion rays, the guide from the first face found, the a-trous
# weights in one exp2). Stop 69: vx 146aa5e (the light cache's sums in a gather pass; its tests
# SharedLight* and AFullTable* run on the NVIDIA driver too).
source docs/render_report/scripts/device_env.sh
source docs/render_report/scripts/seed_mirror_reference.sh
F="--spp 4 --bounce-spp 4 --denoise on --denoise-passes 2 --light-cache on --split-hits 5 --repeat 12"
for seed in 1 2; do
  for bin in vx_base vx; do
    echo "== $bin, sample seed $seed: 4/4 denoised, 2 passes, light cache, split hits 5; versus 25/25 raw"
    timeout 120 $B/$bin render $M $F --sample-seed $seed --versus-raw 25 --out /tmp/img/${bin}_$seed.png 2>&1 |
      grep -E "frames 2|versus|error|fail" | head -3
  done
done
echo "# at $(( $(date +%s) - t0 )) s"
python3 docs/render_report/scripts/rmse_pngs.py /tmp/img/ref.png /tmp/img/vx*_*.png
pre=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1)
echo "# vx_render_tests (denoiser, light cache)"
LD_PRELOAD=$pre VX_TEST_DEVICE=gpu timeout 250 "$B/vx_render_tests" --gtest_filter='*Denois*:*LightCache*:*SplitHits*:*SharedLight*:*AFullTable*' 2>&1 |
  grep -E "^\[  (FAILED|PASSED|SKIPPED) |^\[       OK|Failure|Which is|skip" | head -60
echo "# at $(( $(date +%s) - t0 )) s"
