#!/usr/bin/env bash
# Stop 60's device call. 1) The render tests of the bent finite lights, the G-buffer comparisons
# within a few roundings (gbuffer_compare.h) and the sky's, on the NVIDIA driver (vx_render_tests
# of this stop: the area light and the faces in one finite_light()). 2) Timings, two alternated
# rounds: stop 58's sky walk (vx_sky, 47e89bb) and with a call site per kind (vx_sky2, sky2.patch),
# stop 59's bent finite lights (vx_lt, c7d6ee4) and this stop's (vx_fl) on the terrain T and the
# deep pond P; the lamp pond L (make_lamp_pond.py, at night) with vx_lt and vx_fl.
source docs/render_report/scripts/device_env.sh > /dev/null
source docs/render_report/scripts/device_scenes.sh
python3 docs/render_report/finite-light-2026-12-07/make_lamp_pond.py "$D/lamp.raw"
L="--raw $D/lamp.raw --dims 96,24,96 --type u8 --eye 48,30,8 --target 48,12,42 --size 1920x1080 --device gpu"
L="$L --spp 4 --reflections 2 --sun off --sky-light 0 --exposure auto --repeat 12"
pre=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1)
LD_PRELOAD=$pre VX_TEST_DEVICE=gpu timeout 200 "$B/vx_render_tests" \
  --gtest_filter='*SplitHits*:*SeeThroughCheck*:*ShadowRaysThroughGlassAlone*:*UnderWater*:*Snell*:*AboveWater*:*MeetTheRoof*:*EachHitUnderWater*:*Emitter*' \
  2>&1 |
  grep -E "differ|roundings|RMS|^\[  (FAILED|PASSED|     OK)|Failure|tests from .* ran" | head -80
echo "# at $(( $(date +%s) - t0 )) s"
for round in 1 2; do
  echo "# round $round"
  one T_sky vx_sky $T; one T_sky2 vx_sky2 $T; one T_lt vx_lt $T; one T_fl vx_fl $T
  one P_sky vx_sky $P; one P_sky2 vx_sky2 $P; one P_lt vx_lt $P; one P_fl vx_fl $P
  one L_lt vx_lt $L; one L_fl vx_fl $L
  echo "# at $(( $(date +%s) - t0 )) s"
done
(cd "$D" && md5sum *.png | sort)
