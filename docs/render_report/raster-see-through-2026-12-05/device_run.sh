#!/bin/bash
# Device call (2026-12-05, stop 49): the raster see-through pass drawing only the transparent
# faces (one instance per face from a per-frame list) against every slot of the chunk again.
# Binaries: vx_prev (main before the change: f084bb1's renderer), vx (the list). The scattered
# stone / water volumes of ../raster-transparency-2026-12-05, raster Flat and Full, 1080p, three
# alternated rounds; then the render suites with validation on.
source docs/render_report/scripts/device_env.sh
cd docs/render_report/raster-transparency-2026-12-05
for round in 1 2 3; do
  for shading in flat full; do
    for b in stone water; do
      for bin in vx_prev vx; do
        printf "raster %-4s round %s %-5s %-7s " $shading $round $b $bin
        timeout 60 $B/$bin render --raw "$D/scatter_$b.raw" $V --pipeline raster --shading $shading \
          --out "$D/${shading}_${b}_$bin.png" 2>&1 | grep "frames 2"
      done
    done
  done
done
for shading in flat full; do
  for b in stone water; do
    cmp "$D/${shading}_${b}_vx.png" "$D/${shading}_${b}_vx_prev.png" && echo "$shading $b: images identical"
  done
done
cp "$D"/*water*.png $OUT/ 2>/dev/null
cd - >/dev/null
echo "elapsed $(( $(date +%s) - t0 )) s"
export LD_PRELOAD=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1) # Static TLS: see render_report.md.
for t in vx_render_tests vx_cli_render_tests; do
  echo "== $t"
  VX_TEST_DEVICE=gpu timeout 300 $B/$t --gtest_brief=1 > $OUT/$t.log 2>&1; echo "rc=$?"
  grep -E "FAILED|PASSED|tests ran|SKIPPED" $OUT/$t.log | head -20
  echo "elapsed $(( $(date +%s) - t0 )) s"
done
echo "total: $(( $(date +%s) - t0 )) s"
