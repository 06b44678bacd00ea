#!/bin/bash
# Device call (2026-12-06, stop 55): the cost of pairing touching see-through faces in the shadow
# rays' any-hit (a payload 16 bytes larger for every shadow ray; the pairing itself only in the
# probing variant) and of the sky rays' walk taking one share per interface. Binaries: vx_base
# (main at 0bce48b) and vx (this stop). Scenes P, S, T of scripts/device_scenes.sh (no two
# different see-through blocks touch: their images must be byte-identical) and M, the scattered
# volume with water and glass mixed (make_mixed.py: the probing variant, pairs everywhere).
# GPU trace medians of frames 2..N, three alternated rounds; then the render test programs with
# the validation layer (VX_TEST_DEVICE=gpu), built from this stop's code.
# (Since the call, scene M comes from scripts/device_scenes.sh: the same renders.)
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
source docs/render_report/scripts/device_env.sh
source docs/render_report/scripts/device_scenes.sh
alternated_rounds 3 "vx_base vx" "P S T M" 2>&1 | tee $OUT/rounds.log
(cd $D && md5sum *.png | sort) | tee $OUT/md5.log
cp $D/M_vx.png $D/M_vx_base.png $OUT/ 2>/dev/null
bash docs/render_report/touching-pairs-2026-12-05/device_suites.sh 2>&1 | grep -E "==|rc=|PASSED|FAILED|SKIPPED  \]|elapsed"
echo "total: $(( $(date +%s) - t0 )) s"
