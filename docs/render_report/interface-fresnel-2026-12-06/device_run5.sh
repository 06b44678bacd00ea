#!/bin/bash
# Device call 5 (2026-12-06, stop 55): sky rays from under water bent where they leave it
# (kWalkSky: Snell's window). Binaries: vx_dead (3e14aba) and vx_sky (1c7865b). Scenes P, S, T
# as device_run.sh's; three alternated rounds; then the render tests of see-through blocks, the
# sun and the sky with the validation layer (VX_TEST_DEVICE=gpu), built at 1c7865b.
# (Since the call, the test run comes from scripts/device_scenes.sh: the same tests.)
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
source docs/render_report/scripts/device_env.sh
source docs/render_report/scripts/device_scenes.sh
alternated_rounds 3 "vx_dead vx_sky" "P S T" 2>&1 | tee $OUT/rounds.log
(cd $D && md5sum *.png | sort) | tee $OUT/md5.log
filtered_render_tests '*Sun*:*Pool*:*Water*:*Lake*:*Interface*:*OneIndex*:*Transparen*:*Glass*:*Sky*' # LD_PRELOAD for static TLS: render_report.md.
echo "total: $(( $(date +%s) - t0 )) s"
