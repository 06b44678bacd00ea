#!/bin/bash
# Lavapipe (this VM), stop 51: what the see-through body change costs or saves. Binaries: $1 (the
# old code) and $2 (this stop), alternated, three rounds, on the scattered volumes of
# raster-transparency-2026-12-05/make_scatter.py (stone: no see-through block, the images must be
# identical; water: 10% water scattered, much of it against stone or ground):
#  - raster, Flat, 320x180: the GPU raster pass, median of frames 2..10 (the transparent pass
#    now culls back faces);
#  - ray traced, Full, 4 spp, 2 reflections, 160x90: the GPU trace, median of frames 2..5.
# Usage (repository root): bash docs/render_report/see-through-body-2026-12-05/lavapipe_run.sh OLD_VX NEW_VX
set -u
OLD=$1 NEW=$2
D=$(mktemp -d)
python3 docs/render_report/raster-transparency-2026-12-05/make_scatter.py "$D"
V="--dims 256,48,256 --type u8 --eye 128,70,-60 --target 128,20,128"
for round in 1 2 3; do
  for vol in stone water; do
    for bin in old new; do
      vx=$OLD; [ $bin = new ] && vx=$NEW
      printf "round %s raster %-5s %-3s " $round $vol $bin
      "$vx" render --raw "$D/scatter_$vol.raw" $V --pipeline raster --shading flat --size 320x180 --repeat 10 \
        --out "$D/raster_${vol}_$bin.png" 2>&1 | grep "frames 2"
      printf "round %s traced %-5s %-3s " $round $vol $bin
      "$vx" render --raw "$D/scatter_$vol.raw" $V --size 160x90 --spp 4 --reflections 2 --repeat 5 \
        --out "$D/traced_${vol}_$bin.png" 2>&1 | grep "frames 2"
    done
  done
done
for p in raster traced; do
  for vol in stone water; do
    cmp -s "$D/${p}_${vol}_old.png" "$D/${p}_${vol}_new.png" && echo "$p $vol: identical" || echo "$p $vol: differ"
  done
done
echo "images: $D"
