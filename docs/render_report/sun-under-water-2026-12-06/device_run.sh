#!/bin/bash
# Device call (2026-12-06, stop 54): what bending the sun's light at points inside water and glass
# (sun_through, shaders/raygen.rgen) costs on the NVIDIA driver. Binaries: vx (f6d1a0e, stop 53's
# shaders: one straight any-hit shadow ray per sun sample) and vx_sun (8532a1d: from a point inside
# a see-through block, one walk per axis facing the sun). GPU trace medians of frames 2..N, three
# alternated rounds, 1920x1080, 4 spp: the deep pond (absorption-2026-12-06/make_deep_pond.py),
# the scattered stone and water volume (D, V: device_env.sh) and the terrain of the main job
# (seed 1). Then the render test programs with the validation layer (VX_TEST_DEVICE=gpu) at 8532a1d.
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
source docs/render_report/scripts/device_env.sh
python3 docs/render_report/absorption-2026-12-06/make_deep_pond.py "$D/deep.raw"
P="--raw $D/deep.raw --dims 96,24,96 --type u8 --eye 48,30,8 --target 48,12,42 --size 1920x1080 --device gpu --spp 4 --reflections 2 --repeat 12"
S="--raw $D/scatter_water.raw $V --spp 4"
T="--seed 1 --size 1920x1080 --device gpu --spp 4 --repeat 12"
for round in 1 2 3; do
  for bin in vx vx_sun; do
    for scene in P S T; do
      printf "round %s %s %-6s " $round $scene $bin
      timeout 90 $B/$bin render ${!scene} --out "$D/${scene}_$bin.png" > /tmp/r.txt 2>&1; grep "frames 2" /tmp/r.txt | sed 's/, readback.*//' || tail -3 /tmp/r.txt
    done
  done
  echo "elapsed $(( $(date +%s) - t0 )) s"
done
(cd $D && md5sum *.png)
cp .devbuild/vx_sun /work/main/build/release/tools/vx && cp .devbuild/vx_sun .devbuild/vx # The CLI tests run this stop's vx.
bash docs/render_report/touching-pairs-2026-12-05/device_suites.sh # The render suites, validation on.
echo "total: $(( $(date +%s) - t0 )) s"
