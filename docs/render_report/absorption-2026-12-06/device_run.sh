#!/bin/bash
# Device call (2026-12-06, stop 53): what Beer-Lambert absorption and the bent view cost on the
# NVIDIA driver. Binaries: vx_52 (5c250db, stop 52: one albedo per block crossed, straight views)
# and vx (f6d1a0e: absorption along the path, the eye's walk bent by Snell's law). GPU trace medians of frames 2..N, three alternated rounds, at 1920x1080 on: the
# deep pond (make_deep_pond.py), the scattered stone and water volume of raster-transparency-
# 2026-12-05 (D, V: device_env.sh) and the terrain of the main job (seed 1). Then the render test
# programs with the validation layer (VX_TEST_DEVICE=gpu), this stop's code.
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
source docs/render_report/scripts/device_env.sh
HERE=docs/render_report/absorption-2026-12-06
python3 $HERE/make_deep_pond.py "$D/deep.raw"
P="--raw $D/deep.raw --dims 96,24,96 --type u8 --eye 48,30,8 --target 48,12,42 --size 1920x1080 --device gpu --spp 4 --reflections 2 --repeat 12"
S="--raw $D/scatter_water.raw $V --spp 4"
T="--seed 1 --size 1920x1080 --device gpu --spp 4 --repeat 12"
for round in 1 2 3; do
  for bin in vx_52 vx; do
    for scene in P S T; do
      printf "round %s %s %-6s " $round $scene $bin
      timeout 90 $B/$bin render ${!scene} --out "$D/${scene}_$bin.png" > /tmp/r.txt 2>&1; grep "frames 2" /tmp/r.txt || tail -3 /tmp/r.txt
    done
  done
  echo "elapsed $(( $(date +%s) - t0 )) s"
done
cp "$D"/P_vx_52.png "$D"/P_vx.png $OUT/
bash docs/render_report/touching-pairs-2026-12-05/device_suites.sh # The render suites, validation on.
echo "total: $(( $(date +%s) - t0 )) s"
