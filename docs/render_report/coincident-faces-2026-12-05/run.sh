#!/bin/bash
# The coincident-face probe's cost (render_report.md, "Touching transparent blocks in the ray
# tracer"): two vx binaries, before and after, alternated over three rounds on terrain with a
# lake and on the scattered stone / water volumes of ../raster-transparency-2026-12-05.
# Usage: bash run.sh OLD_VX NEW_VX [--device gpu] [--size WxH]   (lavapipe: VK_DRIVER_FILES set)
set -eu
OLD=$1 NEW=$2
shift 2
HERE=$(cd "$(dirname "$0")" && pwd)
D=$(mktemp -d)
python3 "$HERE/../raster-transparency-2026-12-05/make_scatter.py" "$D"
EXTRA=("$@")
[ ${#EXTRA[@]} -eq 0 ] && EXTRA=(--size 320x180)
for round in 1 2 3; do
  for bin in "$OLD" "$NEW"; do
    printf "lake  round %s %-40s " $round "$bin"
    "$bin" render --seed 7 --radius 3 --repeat 6 --spp 4 --reflections 2 "${EXTRA[@]}" --out "$D/lake.png" 2>&1 | grep "frames 2"
  done
done
for round in 1 2 3; do
  for b in stone water; do
    for bin in "$OLD" "$NEW"; do
      printf "%-5s round %s %-40s " $b $round "$bin"
      "$bin" render --raw "$D/scatter_$b.raw" --dims 256,48,256 --type u8 --eye 128,70,-60 --target 128,20,128 \
        --repeat 6 --spp 4 --reflections 2 "${EXTRA[@]}" --out "$D/$b.png" 2>&1 | grep "frames 2"
    done
  done
done
rm -rf "$D"
