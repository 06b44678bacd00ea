#!/bin/bash
# Device call (2026-12-06, stop 54): what bending the sun's light at points inside water and glass
# (sun_through, shaders/raygen.rgen) costs on the NVIDIA driver. Binaries: vx (f6d1a0e, stop 53's
# shaders: one straight any-hit shadow ray per sun sample) and vx_sun (8532a1d: from a point inside
# a see-through block, one walk per axis facing the sun). GPU trace medians of frames 2..N, three
# alternated rounds, 1920x1080, 4 spp: the deep pond (absorption-2026-12-06/make_deep_pond.py),
# the scattered stone and water volume (D, V: device_env.sh) and the terrain of the main job
# (seed 1). Then the render test programs with the validation layer (VX_TEST_DEVICE=gpu) at 8532a1d.
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
# (Since the call, the scenes and the loop come from scripts/device_scenes.sh: the same renders.)
source docs/render_report/scripts/device_env.sh
source docs/render_report/scripts/device_scenes.sh
alternated_rounds 3 "vx vx_sun" "P S T"
(cd $D && md5sum *.png)
cp .devbuild/vx_sun /work/main/build/release/tools/vx && cp .devbuild/vx_sun .devbuild/vx # The CLI tests run this stop's vx.
bash docs/render_report/touching-pairs-2026-12-05/device_suites.sh # The render suites, validation on.
echo "total: $(( $(date +%s) - t0 )) s"
