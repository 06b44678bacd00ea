#!/usr/bin/env bash
# Stop 58's second device call. 1) The two tests that failed on the NVIDIA driver in call 1
# (device_run3.sh: 2 and 3 G-buffer pixels differing, the 8-bit images equal), now comparing the
# G-buffers within a few roundings of their storage off Mesa (tests/render/gbuffer_compare.h),
# printing the largest difference; with the check's and the sky's tests (vx_render_tests of
# 8a302d3). 2) The bent sky's cost with two call sites of the walk, one per kind (vx_sky2:
# 47e89bb with sky2.patch, stripped by hand), against one call site of a kind decided at run time
# (vx_sky, 47e89bb) and stop 57's final code (vx, 2aaf7e7). 3) Stop 59's bent area light and
# emitter faces from under water (vx_lt; the tests *UnderWater*, *AboveWater* in vx_render_tests).
source docs/render_report/scripts/device_env.sh > /dev/null
source docs/render_report/scripts/device_scenes.sh
pre=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1)
LD_PRELOAD=$pre VX_TEST_DEVICE=gpu timeout 200 "$B/vx_render_tests" \
  --gtest_filter='*SplitHits*:*SeeThroughCheck*:*ShadowRaysThroughGlassAlone*:*UnderWater*:*Snell*:*AboveWater*:*MeetTheRoof*' \
  2>&1 |
  grep -E "differ|roundings|RMS|^\[  (FAILED|PASSED|     OK)|Failure|tests from .* ran" | head -60
echo "# at $(( $(date +%s) - t0 )) s"
for round in 1 2; do
  echo "# round $round"
  one T_on vx $T; one T_sky vx_sky $T; one T_sky2 vx_sky2 $T; one T_lt vx_lt $T
  one P_on vx $P; one P_sky vx_sky $P; one P_sky2 vx_sky2 $P; one P_lt vx_lt $P
  echo "# at $(( $(date +%s) - t0 )) s"
done
(cd "$D" && md5sum *.png | sort)
