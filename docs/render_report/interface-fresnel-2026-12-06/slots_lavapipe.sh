#!/bin/bash
# Lavapipe (this VM), stop 55: how many pairs two payload slots lose against four and sixteen, on
# the water-and-glass volume (make_mixed.py) at 128x72. Build vx with kShadowPending (shaders/
# shared/rt_common.glsl) at 4 and at 16 and pass the binaries; prints each image's difference from
# the first (scripts/compare_png.py). About 3 minutes a render.
# Usage (repository root): bash <this file> VX_2_SLOTS VX_4_SLOTS VX_16_SLOTS
set -eu
D=$(mktemp -d)
python3 docs/render_report/interface-fresnel-2026-12-06/make_mixed.py "$D"
V="--dims 256,48,256 --type u8 --eye 128,70,-60 --target 128,20,128 --size 128x72 --repeat 1 --spp 4 --reflections 2"
i=0
for b in "$@"; do
  i=$((i + 1))
  "$b" render --raw "$D/scatter_mixed.raw" $V --out "$D/slots_$i.png" > /dev/null
done
python3 scripts/compare_png.py "$D"/slots_*.png
