#!/usr/bin/env bash
# Stop 58's second device call: the two tests that failed on the NVIDIA driver in call 1
# (device_run3.sh: 2 and 3 G-buffer pixels differing, the 8-bit images equal), now comparing the
# G-buffers within a few roundings of their storage off Mesa (tests/render/gbuffer_compare.h),
# printing the largest difference; and the check's and the sky's tests. vx_render_tests of this
# commit, stripped by hand.
source docs/render_report/scripts/device_env.sh > /dev/null
pre=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1)
LD_PRELOAD=$pre VX_TEST_DEVICE=gpu timeout 200 "$B/vx_render_tests" \
  --gtest_filter='*SplitHits*:*SeeThroughCheck*:*ShadowRaysThroughGlassAlone*:*UnderWater*:*Snell*' 2>&1 |
  grep -E "differ|roundings|RMS|^\[  (FAILED|PASSED|     OK)|Failure|tests from .* ran" | head -60
echo "# at $(( $(date +%s) - t0 )) s"
