#!/bin/bash
# The raster baseline's transparent pass, its cost: the same meshes with the scattered blocks
# opaque (stone: one pass) and see-through (water: two passes), alternated, 3 rounds.
# Usage: bash run.sh [path/to/vx]   (from this folder; lavapipe: VK_DRIVER_FILES set by the caller)
set -eu
VX=${1:-../../../build/release/tools/vx}
D=$(mktemp -d)
python3 make_scatter.py "$D"
for round in 1 2 3; do
  for b in stone water; do
    printf "round %s %-5s " $round $b
    "$VX" render --raw "$D/scatter_$b.raw" --dims 256,48,256 --type u8 --pipeline raster --shading flat \
      --size 320x180 --eye 128,70,-60 --target 128,20,128 --repeat 10 --out "$D/$b.png" 2>&1 | grep "frames 2"
  done
done
rm -rf "$D"
