#!/bin/bash
# Device call 2 (2026-12-06, stop 54): the sun's ways in under a Russian roulette. Binaries: vx
# (f6d1a0e, stop 53: straight sun rays), vx_sun (8532a1d: every way in traced) and vx_rr (the
# stop's last code: the way from above always, the others by chance min(1, w_k / w_y)). GPU trace
# medians of frames 2..N, three alternated rounds, the scenes of device_run.sh. Then the render test
# programs with the validation layer (VX_TEST_DEVICE=gpu), built from the same code as vx_rr.
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
# (Since the call, the scenes and the loop come from scripts/device_scenes.sh: the same renders.)
source docs/render_report/scripts/device_env.sh
source docs/render_report/scripts/device_scenes.sh
alternated_rounds 3 "vx vx_sun vx_rr" "P S T"
(cd $D && md5sum *.png | sort)
cp .devbuild/vx_rr /work/main/build/release/tools/vx && cp .devbuild/vx_rr .devbuild/vx # The CLI tests run this stop's vx.
bash docs/render_report/touching-pairs-2026-12-05/device_suites.sh 2>&1 | grep -E "==|rc=|PASSED|FAILED|SKIPPED  \]|elapsed"
echo "total: $(( $(date +%s) - t0 )) s"
