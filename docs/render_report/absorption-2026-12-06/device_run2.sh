#!/bin/bash
# Device call 2 (2026-12-06, stop 53): where the +26% (scattered water) and +5% (terrain) of call 1
# come from: vx_52 (5c250db, stop 52), vx_bl (a3828cb's shaders: absorption alone) and vx (f6d1a0e:
# absorption and the bent view), three alternated rounds, GPU trace medians.
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
source docs/render_report/scripts/device_env.sh
S="--raw $D/scatter_water.raw $V --spp 4"
T="--seed 1 --size 1920x1080 --device gpu --spp 4 --repeat 12"
for round in 1 2 3; do
  for bin in vx_52 vx_bl vx; do
    for scene in S T; do
      printf "round %s %s %-6s " $round $scene $bin
      timeout 90 $B/$bin render ${!scene} --out "$D/${scene}_$bin.png" > /tmp/r.txt 2>&1; grep "frames 2" /tmp/r.txt | sed 's/, readback.*//' || tail -3 /tmp/r.txt
    done
  done
done
echo "total: $(( $(date +%s) - t0 )) s"
