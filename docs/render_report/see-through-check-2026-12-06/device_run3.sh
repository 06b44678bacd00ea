#!/usr/bin/env bash
# Stop 58's device call. It replaces stop 57's device_run2.sh, which never ran: stop 57's final
# code against stop 56's, S and M checked twice with md5s; then the check's render tests with
# their failures printed in full, and the whole render suite on the NVIDIA driver (the tests of
# 47e89bb). Binaries: build_binaries.sh (vx = 2aaf7e7); vx_sky is 47e89bb (the sky rays bent
# where they leave water, 1c7865b again on the check, with Snell's window sampled), stripped by
# hand from build/release.
source docs/render_report/scripts/device_env.sh > /dev/null
source docs/render_report/scripts/device_scenes.sh
for round in 1 2; do
  echo "# round $round"
  one T_old vx_old $T; one T_off vx $T --see-through-check off; one T_on vx $T
  one T_sky vx_sky $T; one T_sky_off vx_sky $T --see-through-check off
  one P_old vx_old $P; one P_off vx $P --see-through-check off; one P_on vx $P; one P_sky vx_sky $P
  echo "# at $(( $(date +%s) - t0 )) s"
done
S1="--raw $D/scatter_water.raw --dims 256,48,256 --type u8 --eye 128,70,-60 --target 128,20,128 --device gpu --size 1920x1080 --spp 4"
M1="--raw $D/scatter_mixed.raw --dims 256,48,256 --type u8 --eye 128,70,-60 --target 128,20,128 --device gpu --size 1920x1080 --spp 4"
for sc in S1 M1; do
  one "${sc}_off" vx ${!sc} --see-through-check off
  one "${sc}_all_1" vx ${!sc} --see-through-check-share 1
  one "${sc}_all_2" vx ${!sc} --see-through-check-share 1
  one "${sc}_sky" vx_sky ${!sc}
done
echo "# md5 of each render's PNG"
(cd "$D" && md5sum *.png | sort)
echo "# at $(( $(date +%s) - t0 )) s"
echo "# the check's render tests on the NVIDIA driver, failures in full"
pre=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1)
LD_PRELOAD=$pre VX_TEST_DEVICE=gpu timeout 120 "$B/vx_render_tests" --gtest_brief=1 \
  --gtest_filter='*SeeThroughCheck*:*ShadowRaysThroughGlassAlone*:*WithoutSeeThroughBlocks*:*Transparent*' \
  > "$OUT/check_tests.txt" 2>&1
grep -v "^vx error: out of memory" "$OUT/check_tests.txt" | head -60
echo "# at $(( $(date +%s) - t0 )) s"
echo "# the whole render suite on the NVIDIA driver (failures only)"
LD_PRELOAD=$pre VX_TEST_DEVICE=gpu timeout 200 "$B/vx_render_tests" --gtest_brief=1 > "$OUT/render_tests.txt" 2>&1
echo "rc $?"; grep -E "^\[  FAILED|^\[  PASSED|tests from .* ran" "$OUT/render_tests.txt" | head -40
echo "# at $(( $(date +%s) - t0 )) s"
