#!/bin/bash
# Device call 3 (2026-12-06, stop 54): call 2 found the roulette (vx_rr, 4440f59) slower on the
# H100 than every way traced (vx_sun, 8532a1d): 11.4 against 9.6 ms on the deep pond. vx_rr2 works
# each way's direction and weight out again per way instead of keeping them in arrays across the
# walks' traces (the same images). GPU trace medians, the scenes of device_run.sh; timings only
# (the device time left did not cover the suites again).
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
# (Since the call, the scenes and the loop come from scripts/device_scenes.sh: the same renders.)
source docs/render_report/scripts/device_env.sh
source docs/render_report/scripts/device_scenes.sh
alternated_rounds 3 "vx_sun vx_rr vx_rr2" "P"
alternated_rounds 1 "vx_sun vx_rr2" "S"
alternated_rounds 1 "vx_rr2" "T"
(cd $D && md5sum P_*.png S_*.png | sort)
echo "total: $(( $(date +%s) - t0 )) s"
