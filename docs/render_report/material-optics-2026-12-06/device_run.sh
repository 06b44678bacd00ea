#!/bin/bash
# Device call (2026-12-06, stop 54): what working out each see-through block's absorption
# coefficient and index of refraction once, on upload (render/material_table.h), saves against
# working them out per ray. Binaries: vx (f6d1a0e, stop 53's shaders: a log per segment and per
# shadow-ray face, a sqrt and a divide per index) and vx_mt (this stop: both read from the
# material table). GPU trace medians of frames 2..N, three alternated rounds, at 1920x1080 on the
# deep pond (absorption-2026-12-06/make_deep_pond.py), the scattered stone and water volume of
# raster-transparency-2026-12-05 (D, V: device_env.sh) and the terrain of the main job (seed 1).
# Then the render test programs with the validation layer (VX_TEST_DEVICE=gpu), this stop's code.
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
# (Since the call, the scenes and the loop come from scripts/device_scenes.sh: the same renders.)
source docs/render_report/scripts/device_env.sh
source docs/render_report/scripts/device_scenes.sh
alternated_rounds 3 "vx vx_mt" "P S T"
for scene in P S T; do cmp -s "$D/${scene}_vx.png" "$D/${scene}_vx_mt.png" && echo "$scene: images identical" || echo "$scene: images differ"; cp "$D/${scene}_vx.png" "$D/${scene}_vx_mt.png" $OUT/; done
cp .devbuild/vx_mt /work/main/build/release/tools/vx && cp .devbuild/vx_mt .devbuild/vx # The CLI tests run this stop's vx.
bash docs/render_report/touching-pairs-2026-12-05/device_suites.sh # The render suites, validation on.
echo "total: $(( $(date +%s) - t0 )) s"
