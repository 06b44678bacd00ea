#!/bin/bash
# Lavapipe (this VM), stop 52: what water and glass surfaces that mirror (3a1404b) cost. Binaries:
# $1 (the old code) and $2 (this stop), alternated, three rounds, ray traced, Full, 4 spp,
# 2 reflections, 160x90, the GPU trace's median of frames 2..5, on the scattered volumes of
# raster-transparency-2026-12-05/make_scatter.py (stone: no see-through block, the images must be
# identical; water: 10% water scattered in stone: each surface the eye enters now sends a
# reflection ray) and terrain seed 1 (radius 3, lakes).
# Usage (repository root): bash docs/render_report/water-surface-2026-12-06/lavapipe_run.sh OLD_VX NEW_VX
set -u
OLD=$1 NEW=$2
D=$(mktemp -d)
python3 docs/render_report/raster-transparency-2026-12-05/make_scatter.py "$D"
V="--dims 256,48,256 --type u8 --eye 128,70,-60 --target 128,20,128"
for round in 1 2 3; do
  for bin in old new; do
    vx=$OLD; [ $bin = new ] && vx=$NEW
    for vol in stone water; do
      printf "round %s traced %-7s %-3s " $round $vol $bin
      "$vx" render --raw "$D/scatter_$vol.raw" $V --size 160x90 --spp 4 --reflections 2 --repeat 5 \
        --out "$D/traced_${vol}_$bin.png" 2>&1 | grep "frames 2"
    done
    printf "round %s traced %-7s %-3s " $round terrain $bin
    "$vx" render --seed 1 --radius 3 --size 160x90 --spp 4 --repeat 5 --out "$D/traced_terrain_$bin.png" 2>&1 | grep "frames 2"
  done
done
for vol in stone water terrain; do
  cmp -s "$D/traced_${vol}_old.png" "$D/traced_${vol}_new.png" && echo "$vol: identical" || echo "$vol: differ"
done
echo "images: $D"
