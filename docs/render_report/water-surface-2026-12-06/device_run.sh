#!/bin/bash
# Device call (2026-12-06, stop 52): water and glass surfaces mirror as Fresnel says (3a1404b).
# Binaries: vx_base (built at 1ba43b5: 6f7b715's shaders, before stop 51), vx_51 (cfd014f: stop
# 51's whole-albedo tints, never timed on the NVIDIA driver) and vx (this stop). GPU trace medians
# of frames 2..N, three alternated rounds, on
#  - the seed mirror scene at issue 18's one-frame settings (no see-through block: the three
#    images must be identical; what the larger shadow payload, the walk's facing test and the
#    surface's bookkeeping cost),
#  - scatter_water (raster-transparency-2026-12-05/make_scatter.py: water scattered in stone; this
#    stop's images differ: each water surface the eye enters now sends a reflection ray),
#  - terrain seed 1 (lakes).
# Then the render test programs with the validation layer (VX_TEST_DEVICE=gpu).
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
source docs/render_report/scripts/device_env.sh
$B/vx info 2>&1 | tail -2
M="--scene seed --scene-block mirror --size 1920x1080 --device gpu --reflections 5 --split-hits 5 --spp 4 --bounce-spp 4 --denoise on --repeat 12"
T="--seed 1 --radius 6 --size 1920x1080 --device gpu --spp 4 --repeat 12"
for round in 1 2 3; do
  for bin in vx_base vx_51 vx; do
    printf "round %s seed_mirror   %-8s " $round $bin
    timeout 60 $B/$bin render $M --out "$D/seed_$bin.png" > /tmp/r.txt 2>&1; grep "frames 2" /tmp/r.txt || tail -3 /tmp/r.txt
    printf "round %s scatter_water %-8s " $round $bin
    timeout 45 $B/$bin render --raw "$D/scatter_water.raw" $V --spp 4 --reflections 2 --out "$D/water_$bin.png" > /tmp/r.txt 2>&1; grep "frames 2" /tmp/r.txt || tail -3 /tmp/r.txt
    printf "round %s terrain       %-8s " $round $bin
    timeout 45 $B/$bin render $T --out "$D/terrain_$bin.png" > /tmp/r.txt 2>&1; grep "frames 2" /tmp/r.txt || tail -3 /tmp/r.txt
  done
  echo "elapsed $(( $(date +%s) - t0 )) s"
done
for s in seed water terrain; do
  for bin in vx_51 vx; do
    cmp -s "$D/${s}_$bin.png" "$D/${s}_vx_base.png" && echo "$s: $bin and vx_base identical" || echo "$s: $bin and vx_base differ"
  done
done
cp "$D"/water_vx*.png "$D"/terrain_vx*.png $OUT/ 2>/dev/null
bash docs/render_report/touching-pairs-2026-12-05/device_suites.sh # The render suites, validation on.
echo "total: $(( $(date +%s) - t0 )) s"
