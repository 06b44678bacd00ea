#!/bin/bash
# Lavapipe (this VM), stop 53: the deep pond of make_deep_pond.py (there) before and after
# Beer-Lambert absorption and the bent view, from above (deep_*.png: 480x270, 16 spp, 2
# reflections, 8 frames accumulated) and from under its water looking up at the surface and the
# pillar (under_*.png: 100 degrees, 4 frames). Binaries $1 (old) and $2 (new); writes into $3
# (default: this folder).
# Usage (repository root): bash docs/render_report/absorption-2026-12-06/pond.sh OLD_VX NEW_VX [DIR]
set -eu
HERE=docs/render_report/absorption-2026-12-06
D=$(mktemp -d)
python3 $HERE/make_deep_pond.py "$D/deep.raw"
bash docs/render_report/scripts/render_old_new.sh "$1" "$2" "${3:-$HERE}/deep" --raw "$D/deep.raw" --dims 96,24,96 \
  --type u8 --eye 48,30,8 --target 48,12,42 --size 480x270 --spp 16 --reflections 2 --accumulate 8
bash docs/render_report/scripts/render_old_new.sh "$1" "$2" "${3:-$HERE}/under" --raw "$D/deep.raw" --dims 96,24,96 \
  --type u8 --eye 40,9,60 --target 48,14,70 --fov 100 --size 480x270 --spp 16 --reflections 2 --accumulate 4
rm -r "$D"
