#!/bin/bash
# Device calls (2026-12-05, stop 49): the coincident-face probe only at marked faces
# (render/touching_faces.h). Binaries: vx_base (main at 128020c: the probe at every transparent
# face of a chunk that may hold a pair), vx (per-face marks), and per call:
#   call 1: vx_cull (vx with the TLAS instances' FACING_CULL_DISABLE, which breaks the probe's
#           culling: on the stone volume, which traces no probe, the flag's cost alone);
#   call 2: vx_noprobe (vx with no face marked: no probe at all; the water volume, where no two
#           different transparent blocks touch, must look the same).
# Then the render suites on the NVIDIA driver with validation on.
# Usage (device): bash device_run.sh OTHER   (OTHER: vx_cull or vx_noprobe)
source docs/render_report/scripts/device_env.sh
OTHER=${1:-vx_noprobe}
$B/vx info 2>&1 | tail -2
cd docs/render_report/raster-transparency-2026-12-05
for round in 1 2 3; do
  for b in water stone; do
    for bin in vx_base vx $OTHER; do
      [ $b = water ] && [ $bin = vx_cull ] && continue
      printf "rt full spp4 round %s %-5s %-8s " $round $b $bin
      timeout 60 $B/$bin render --raw "$D/scatter_$b.raw" $V --spp 4 --reflections 2 --out "$D/${b}_$bin.png" 2>&1 | grep "frames 2"
    done
  done
  for bin in vx_base vx $OTHER; do
    [ $bin = vx_cull ] && continue
    printf "lake seed 7 round %s %-8s " $round $bin
    timeout 60 $B/$bin render --seed 7 --radius 3 --size 1920x1080 --repeat 20 --spp 4 --reflections 2 --device gpu --out /tmp/lake_$bin.png 2>&1 | grep "frames 2"
  done
  echo "elapsed $(( $(date +%s) - t0 )) s"
done
for other in vx_base $OTHER; do
  cmp /tmp/lake_vx.png /tmp/lake_$other.png && echo "lake: vx and $other identical"
  cmp "$D/water_vx.png" "$D/water_$other.png" && echo "water: vx and $other identical"
  cmp "$D/stone_vx.png" "$D/stone_$other.png" && echo "stone: vx and $other identical"
done
cp /tmp/lake_*.png "$D"/water_*.png $OUT/ 2>/dev/null
cd - >/dev/null
export LD_PRELOAD=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1) # Static TLS: see render_report.md.
for t in vx_render_tests vx_cli_render_tests; do
  echo "== $t"
  VX_TEST_DEVICE=gpu timeout 300 $B/$t --gtest_brief=1 > $OUT/$t.log 2>&1; echo "rc=$?"
  grep -E "FAILED|PASSED|tests ran|VUID|SKIPPED|G-buffer|Skipped" -A1 $OUT/$t.log | head -40
  echo "elapsed $(( $(date +%s) - t0 )) s"
done
echo "total: $(( $(date +%s) - t0 )) s"
