#!/bin/bash
# Device call 4 (2026-12-06, stop 55). Call 3 found the walk's stop in air with a shadow ray on
# (b933e82) slower on the H100 everywhere: a new trace call site. This variant only drops a dead
# way: the sun's walk ends, without a trace, where it leaves into air along another direction
# than the sun's (no new call site). Binaries: vx_pair (11f372d) and vx_dead (this variant).
# Scenes P, S, T and M as device_run.sh's; three alternated rounds; then the render tests of
# see-through blocks and the sun with the validation layer (VX_TEST_DEVICE=gpu), built with it.
# (Since the call, scene M comes from scripts/device_scenes.sh: the same renders.)
# (Since the call, the test run comes from scripts/device_scenes.sh: the same tests.)
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
source docs/render_report/scripts/device_env.sh
source docs/render_report/scripts/device_scenes.sh
alternated_rounds 3 "vx_pair vx_dead" "P S T M" 2>&1 | tee $OUT/rounds.log
(cd $D && md5sum *.png | sort) | tee $OUT/md5.log
filtered_render_tests '*Sun*:*Pool*:*Water*:*Lake*:*Interface*:*OneIndex*:*Transparen*:*Glass*' # LD_PRELOAD for static TLS: render_report.md.
echo "total: $(( $(date +%s) - t0 )) s"
