#!/bin/bash
# Lavapipe (this VM), stop 54: the pillar in the deep pond of absorption-2026-12-06/make_deep_pond.py
# seen straight down, lit by a low sun in +x alone (no sky term, no area light), before and after
# the sun's light is bent where it enters the water (shadow_*.png: 240x240, 8 spp, 4 frames).
# Binaries $1 (old) and $2 (new); writes into $3 (default: this folder).
# Usage (repository root): bash docs/render_report/sun-under-water-2026-12-06/pond.sh OLD_VX NEW_VX [DIR]
set -eu
HERE=docs/render_report/sun-under-water-2026-12-06
D=$(mktemp -d)
python3 docs/render_report/absorption-2026-12-06/make_deep_pond.py "$D/deep.raw"
bash docs/render_report/scripts/render_old_new.sh "$1" "$2" "${3:-$HERE}/shadow" --raw "$D/deep.raw" --dims 96,24,96 \
  --type u8 --eye 40,45,61 --target 40,0,61.01 --fov 60 --size 240x240 --spp 8 --reflections 1 --sun 1,0.7,0 \
  --sky-light 0 --area-light off --accumulate 4
rm -r "$D"
