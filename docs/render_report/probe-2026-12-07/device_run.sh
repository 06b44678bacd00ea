#!/usr/bin/env bash
# Stop 61's device call; it carries stop 60's, which never ran (sky2.patch's timing left out).
# 1) The render tests of the bent finite lights, the probe's two (a floor under a roof in the
# pool, a lamp in the water) and the G-buffer comparisons within a few roundings
# (gbuffer_compare.h), on the NVIDIA driver (vx_render_tests of this stop). 2) Timings, two
# alternated rounds: stop 58 (vx_sky, 47e89bb), stop 59 (vx_lt, c7d6ee4), stop 60 (vx_fl,
# d48726e) and this stop (vx_pr) on the terrain T and the deep pond P; the lamp pond L
# (make_lamp_pond.py, at night) and the dock pond K (make_dock_pond.py, where the probe runs).
source docs/render_report/scripts/device_env.sh > /dev/null
source docs/render_report/scripts/device_scenes.sh
python3 docs/render_report/finite-light-2026-12-07/make_lamp_pond.py "$D/lamp.raw"
python3 docs/render_report/probe-2026-12-07/make_dock_pond.py "$D/dock.raw"
L="--raw $D/lamp.raw --dims 96,24,96 --type u8 --eye 48,30,8 --target 48,12,42 --size 1920x1080 --device gpu"
L="$L --spp 4 --reflections 2 --sun off --sky-light 0 --exposure auto --repeat 12"
K="--raw $D/dock.raw --dims 96,24,96 --type u8 --eye 40,9.5,44 --target 40,4,60 --size 1920x1080 --device gpu"
K="$K --spp 4 --reflections 2 --repeat 12"
pre=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1)
LD_PRELOAD=$pre VX_TEST_DEVICE=gpu timeout 200 "$B/vx_render_tests" \
  --gtest_filter='*SplitHits*:*SeeThroughCheck*:*ShadowRaysThroughGlassAlone*:*UnderWater*:*Snell*:*AboveWater*:*MeetTheRoof*:*UnderARoof*:*Emitter*' \
  2>&1 |
  grep -E "differ|roundings|RMS|^\[  (FAILED|PASSED|     OK)|Failure|tests from .* ran" | head -80
echo "# at $(( $(date +%s) - t0 )) s"
for round in 1 2; do
  echo "# round $round"
  one T_sky vx_sky $T; one T_lt vx_lt $T; one T_fl vx_fl $T; one T_pr vx_pr $T
  one P_sky vx_sky $P; one P_lt vx_lt $P; one P_fl vx_fl $P; one P_pr vx_pr $P
  one L_lt vx_lt $L; one L_fl vx_fl $L; one L_pr vx_pr $L
  one K_fl vx_fl $K; one K_pr vx_pr $K
  echo "# at $(( $(date +%s) - t0 )) s"
done
(cd "$D" && md5sum *.png | sort)
