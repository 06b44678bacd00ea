#!/usr/bin/env bash
# Stop 57's second device call (binaries: build_binaries.sh). Call 1 found the one-dispatch frames
# 3% slower than stop 56's (vx_old) and checked frames of S and M not byte-identical to one
# dispatch, nor to each other. This call times whether the counting was that cost (vx_nocount:
# none in the see-through variant) against the final code (vx: the pixels marked, only the view
# rays' first walks counted in the see-through variant), and renders S and M twice per setting
# to see which checked images vary from run to run (vx_list: call 1's appended list).
source docs/render_report/scripts/device_env.sh > /dev/null
source docs/render_report/scripts/device_scenes.sh
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
for round in 1 2 3; do
  echo "# round $round"
  one T_old vx_old $T; one T_off vx $T --see-through-check off; one T_on vx $T --see-through-check on; one T_list vx_list $T
  one T_nocount_off vx_nocount $T --see-through-check off; one T_nocount_on vx_nocount $T
  if [ "$round" != 3 ]; then
    one P_old vx_old $P; one P_off vx $P --see-through-check off; one P_nocount_off vx_nocount $P --see-through-check off
    one P_on vx $P; one P_all vx $P --see-through-check-share 1; one P_list_all vx_list $P --see-through-check-share 1
    one S_old vx_old $S; one S_on vx $S
  fi
  echo "# at $(( $(date +%s) - t0 )) s"
done
S1="--raw $D/scatter_water.raw --dims 256,48,256 --type u8 --eye 128,70,-60 --target 128,20,128 --device gpu --size 1920x1080 --spp 4"
M1="--raw $D/scatter_mixed.raw --dims 256,48,256 --type u8 --eye 128,70,-60 --target 128,20,128 --device gpu --size 1920x1080 --spp 4"
for k in 1 2; do
  for sc in S1 M1; do
    one "${sc}_off_$k" vx ${!sc} --see-through-check off
    one "${sc}_all_$k" vx ${!sc} --see-through-check-share 1
    one "${sc}_list_$k" vx_list ${!sc} --see-through-check-share 1
  done
done
echo "# md5 of each render's PNG"
(cd "$D" && md5sum *.png | sort)
echo "# S and M against one dispatch (off_1): pixels differing, RMSE"
for sc in S1 M1; do # Each against the first (pure Python, a minute a pair: the scenes side by side).
  python3 scripts/compare_png.py "$D/${sc}_off_1.png" "$D/${sc}_all_1.png" "$D/${sc}_list_1.png" \
    "$D/${sc}_list_2.png" > "$D/${sc}_cmp.txt" 2>&1 &
done
wait
cat "$D/S1_cmp.txt" "$D/M1_cmp.txt"
echo "# the check's render tests on the NVIDIA driver"
LD_PRELOAD=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1) VX_TEST_DEVICE=gpu timeout 150 \
  "$B/vx_render_tests" --gtest_filter='*SeeThroughCheck*:*ShadowRaysThroughGlassAlone*:*WithoutSeeThroughBlocks*:*Transparent*' \
  2>&1 | grep -E "^\[  (FAILED|PASSED) |Failure|Which is|Expected|differ" | head -40
echo "# at $(( $(date +%s) - t0 )) s"
