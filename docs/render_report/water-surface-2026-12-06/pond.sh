#!/bin/bash
# Lavapipe (this VM), stop 52: the pond of make_pond.py (there) before and after water surfaces
# mirror: 480x270, 16 spp, 2 reflections, 8 frames accumulated. Binaries $1 (old) and $2 (new);
# writes pond_old.png and pond_new.png into $3 (default: this folder).
# Usage (repository root): bash docs/render_report/water-surface-2026-12-06/pond.sh OLD_VX NEW_VX [DIR]
set -eu
HERE=docs/render_report/water-surface-2026-12-06
D=$(mktemp -d)
python3 $HERE/make_pond.py "$D/pond.raw"
bash docs/render_report/scripts/render_old_new.sh "$1" "$2" "${3:-$HERE}/pond" --raw "$D/pond.raw" --dims 96,24,96 \
  --type u8 --eye 48,10,6 --target 48,4.5,50 --size 480x270 --spp 16 --reflections 2 --accumulate 8
rm -r "$D"
