#!/bin/bash
# Device call 3 (2026-12-06, stop 54): call 2 found the roulette (vx_rr, 4440f59) slower on the
# H100 than every way traced (vx_sun, 8532a1d): 11.4 against 9.6 ms on the deep pond. vx_rr2 works
# each way's direction and weight out again per way instead of keeping them in arrays across the
# walks' traces (the same images). GPU trace medians, the scenes of device_run.sh; timings only
# (the device time left did not cover the suites again).
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
source docs/render_report/scripts/device_env.sh
python3 docs/render_report/absorption-2026-12-06/make_deep_pond.py "$D/deep.raw"
P="--raw $D/deep.raw --dims 96,24,96 --type u8 --eye 48,30,8 --target 48,12,42 --size 1920x1080 --device gpu --spp 4 --reflections 2 --repeat 12"
S="--raw $D/scatter_water.raw $V --spp 4"
T="--seed 1 --size 1920x1080 --device gpu --spp 4 --repeat 12"
run() { printf "r%s %s %-7s " $1 $2 $3; timeout 60 $B/$3 render ${!2} --out "$D/${2}_$3.png" > /tmp/r.txt 2>&1; grep "frames 2" /tmp/r.txt | sed 's/.*trace/trace/; s/, readback.*//' || tail -3 /tmp/r.txt; }
for round in 1 2 3; do for bin in vx_sun vx_rr vx_rr2; do run $round P $bin; done; done
run 1 S vx_sun; run 1 S vx_rr2; run 1 T vx_rr2
(cd $D && md5sum P_*.png S_*.png | sort)
echo "total: $(( $(date +%s) - t0 )) s"
