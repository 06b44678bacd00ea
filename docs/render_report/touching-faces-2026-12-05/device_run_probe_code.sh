#!/bin/bash
# Device calls (2026-12-05, stop 49): what the probe's code costs a ray that never probes.
# vx = main at 1eaf8cb; vx_nocode = vx with the probe's branch compiled out (no probe, no code);
# vx_one = vx with the walk and its probes sharing one traceRayEXT call (tried, not kept:
# render_report.md). Call 3 ran vx and vx_nocode only; call 5 (the probe compiled out while no
# face is marked) vx_prev = d5380a1 and vx.
source docs/render_report/scripts/device_env.sh
cd docs/render_report/raster-transparency-2026-12-05
for round in 1 2 3; do
  for b in stone water; do
    for bin in vx vx_one vx_nocode; do
      printf "rt full spp4 round %s %-5s %-9s " $round $b $bin
      timeout 60 $B/$bin render --raw "$D/scatter_$b.raw" $V --spp 4 --reflections 2 --out "$D/${b}_$bin.png" 2>&1 | grep "frames 2"
    done
  done
  for bin in vx vx_one vx_nocode; do
    printf "lake seed 7 round %s %-9s " $round $bin
    timeout 60 $B/$bin render --seed 7 --radius 3 --size 1920x1080 --repeat 20 --spp 4 --reflections 2 --device gpu --out /tmp/lake_$bin.png 2>&1 | grep "frames 2"
  done
done
for b in stone water; do for o in vx_one vx_nocode; do cmp "$D/${b}_vx.png" "$D/${b}_$o.png" && echo "$b: vx and $o identical"; done; done
cmp /tmp/lake_vx.png /tmp/lake_vx_one.png && echo "lake: vx and vx_one identical"
cd - >/dev/null
export VK_LAYER_PATH=/tmp/dl/layer LD_PRELOAD=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1)
VX_TEST_DEVICE=gpu timeout 120 $B/vx_render_tests --gtest_filter='*Touching*:*Glass*:*Transparen*:*Water*' 2>&1 | grep -E "^\[ +(OK|FAILED|PASSED) |Validation Error" | head -20
