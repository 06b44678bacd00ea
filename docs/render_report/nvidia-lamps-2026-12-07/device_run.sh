#!/usr/bin/env bash
# Stop 62's pending device call (docs/render_report.md, "The lamp tests on the NVIDIA driver").
# Asks whether stop 60's one loop over both finite lights (0375e47, `[[dont_unroll]] for (kind`
# in shade()) is what the NVIDIA driver gets wrong and pays for. This code (vx_pr of 672123f,
# vx_render_tests of 11558a1) and two builds of 672123f, byte-identical to it on lavapipe:
#   *_split: split.patch, the loop written out as two calls of finite_light() (stop 59 had two
#            functions); lavapipe's cold compile of the terrain 50 s against 34 s;
#   *_unroll: the loop marked `[[unroll]]` (a hint; lavapipe compiles it as the loop).
# 1) With each: the three lamp tests that fail on the H100 (1,056, 7 and 351 of 2,304 floor
#    pixels off), the roof test, and the accumulated frames' noise (AverageOut: 32 frames keep
#    0.19 of one frame's on lavapipe, asserted < 0.25).
# 2) Trace times, two alternated rounds: stop 59 (vx_lt, c7d6ee4, before the loop), this code
#    and the two builds, on the terrain T (14.4 -> 22.0 ms at the loop) and the lamp pond L
#    (25.8 -> 51.5 ms).
# device_env.sh's copy of .devbuild/vx (the CLI tests' binary, left out for the carry limit)
# fails harmlessly.
# Stop 63 ran it (call2.log) with all these binaries rebuilt from e2b3b46, whose renderer is
# 672123f's.
source docs/render_report/scripts/device_env.sh > /dev/null
source docs/render_report/scripts/device_scenes.sh
python3 docs/render_report/finite-light-2026-12-07/make_lamp_pond.py "$D/lamp.raw"
L="--raw $D/lamp.raw --dims 96,24,96 --type u8 --eye 48,30,8 --target 48,12,42 --size 1920x1080 --device gpu"
L="$L --spp 4 --reflections 2 --sun off --sky-light 0 --exposure auto --repeat 12"
pre=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1)
for bin in vx_render_tests vx_render_tests_split vx_render_tests_unroll; do
  echo "# $bin"
  LD_PRELOAD=$pre VX_TEST_DEVICE=gpu timeout 150 "$B/$bin" \
    --gtest_filter='*ALampAbove*:*AreaLightAndALamp*:*ALampUnder*:*UnderARoofIn*:*AverageOut*' \
    2>&1 | grep -E "roughness|Which is|^\[  (FAILED|     OK)" | grep -v "listed below" | head -12
done
echo "# at $(( $(date +%s) - t0 )) s"
for round in 1 2; do
  echo "# round $round"
  one T_lt vx_lt $T; one T_pr vx_pr $T; one T_split vx_split $T; one T_unroll vx_unroll $T
  one L_lt vx_lt $L; one L_pr vx_pr $L; one L_split vx_split $L; one L_unroll vx_unroll $L
  echo "# at $(( $(date +%s) - t0 )) s"
done
(cd "$D" && md5sum *.png | sort)
