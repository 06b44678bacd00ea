#!/bin/bash
# Device call 73 (2026-12-05): the render test suites on the NVIDIA driver with validation on
# (the coincident-face probes cull by facing: the facing rule on a second driver); the probe's
# cost (vx_old: main before it, vx: with it), rt and raster on the scattered-water volumes.
set -u
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
mkdir -p /tmp/dl && tar xzf .devlibs/libs.tgz -C /tmp/dl
export LD_LIBRARY_PATH=/tmp/dl/lib
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export VK_LAYER_PATH=/tmp/dl/layer
chmod +x .devbuild/*
mkdir -p /work/main/build/release/tools && cp .devbuild/vx /work/main/build/release/tools/vx
t0=$(date +%s)
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
.devbuild/vx info 2>&1 | head -6
for t in vx_render_tests vx_facade_render_tests vx_engine_render_tests vx_cli_render_tests; do
  echo "== $t"
  VX_TEST_DEVICE=gpu timeout 150 .devbuild/$t --gtest_brief=1 > $OUT/$t.log 2>&1; echo "rc=$?"
  grep -E "FAILED|PASSED|tests ran|VUID" $OUT/$t.log | head -30
  echo "elapsed $(( $(date +%s) - t0 )) s"
done
cd docs/render_report/raster-transparency-2026-12-05
D=$(mktemp -d); python3 make_scatter.py "$D"
V="--dims 256,48,256 --type u8 --eye 128,70,-60 --target 128,20,128 --device gpu --size 1920x1080 --repeat 20"
for round in 1 2 3; do
  for b in stone water; do
    for bin in vx_old vx; do
      printf "rt full spp4 round %s %-5s %-6s " $round $b $bin
      timeout 60 ../../../.devbuild/$bin render --raw "$D/scatter_$b.raw" $V --spp 4 --reflections 2 --out "$D/${b}_$bin.png" 2>&1 | grep "frames 2"
    done
    printf "raster flat round %s %-5s " $round $b
    timeout 60 ../../../.devbuild/vx render --raw "$D/scatter_$b.raw" $V --pipeline raster --shading flat --out "$D/r_$b.png" 2>&1 | grep "frames 2"
  done
done
cd /tmp
for round in 1 2 3; do
  for bin in vx_old vx; do
    printf "lake seed 7 round %s %-6s " $round $bin
    timeout 60 $OLDPWD/../../../.devbuild/$bin render --seed 7 --radius 3 --size 1920x1080 --repeat 20 --spp 4 --reflections 2 --device gpu --out /tmp/lake_$bin.png 2>&1 | grep "frames 2"
  done
done
cp /tmp/lake_vx.png /tmp/lake_vx_old.png $OUT/ 2>/dev/null
cp "$D"/water_vx.png "$D"/water_vx_old.png $OUT/ 2>/dev/null
echo "total: $(( $(date +%s) - t0 )) s"
