#!/bin/bash
# Device call 3 (2026-12-06, stop 55): the sun's walk from under water stopping where it leaves
# the blocks into air (a shadow ray from there; a way leaving along another direction dropped).
# Binaries: vx_base (main at 0bce48b), vx_pair (11f372d: the interface pairing, call 2's vx) and vx
# (b933e82: also the walk's stop in air). Scenes as device_run.sh's; three alternated rounds. Then
# the render test programs with the validation layer (VX_TEST_DEVICE=gpu), built at b933e82.
# (Since the call, scene M comes from scripts/device_scenes.sh: the same renders.)
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
source docs/render_report/scripts/device_env.sh
source docs/render_report/scripts/device_scenes.sh
alternated_rounds 3 "vx_base vx_pair vx" "P S T M" 2>&1 | tee $OUT/rounds.log
(cd $D && md5sum *.png | sort) | tee $OUT/md5.log
cp $D/P_vx.png $D/P_vx_pair.png $D/S_vx.png $D/S_vx_pair.png $OUT/ 2>/dev/null
bash docs/render_report/touching-pairs-2026-12-05/device_suites.sh 2>&1 | grep -E "==|rc=|PASSED|FAILED|SKIPPED  \]|elapsed"
echo "total: $(( $(date +%s) - t0 )) s"
