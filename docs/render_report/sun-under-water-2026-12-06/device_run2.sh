#!/bin/bash
# Device call 2 (2026-12-06, stop 54): the sun's ways in under a Russian roulette. Binaries: vx
# (f6d1a0e, stop 53: straight sun rays), vx_sun (8532a1d: every way in traced) and vx_rr (the
# stop's last code: the way from above always, the others by chance min(1, w_k / w_y)). GPU trace
# medians of frames 2..N, three alternated rounds, the scenes of device_run.sh. Then the render test
# programs with the validation layer (VX_TEST_DEVICE=gpu), built from the same code as vx_rr.
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
source docs/render_report/scripts/device_env.sh
python3 docs/render_report/absorption-2026-12-06/make_deep_pond.py "$D/deep.raw"
P="--raw $D/deep.raw --dims 96,24,96 --type u8 --eye 48,30,8 --target 48,12,42 --size 1920x1080 --device gpu --spp 4 --reflections 2 --repeat 12"
S="--raw $D/scatter_water.raw $V --spp 4"
T="--seed 1 --size 1920x1080 --device gpu --spp 4 --repeat 12"
for round in 1 2 3; do
  for bin in vx vx_sun vx_rr; do
    for scene in P S T; do
      printf "r%s %s %-6s " $round $scene $bin
      timeout 90 $B/$bin render ${!scene} --out "$D/${scene}_$bin.png" > /tmp/r.txt 2>&1; grep "frames 2" /tmp/r.txt | sed 's/.*trace/trace/; s/, readback.*//' || tail -3 /tmp/r.txt
    done
  done
done
(cd $D && md5sum *.png | sort)
cp .devbuild/vx_rr /work/main/build/release/tools/vx && cp .devbuild/vx_rr .devbuild/vx # The CLI tests run this stop's vx.
bash docs/render_report/touching-pairs-2026-12-05/device_suites.sh 2>&1 | grep -E "==|rc=|PASSED|FAILED|SKIPPED  \]|elapsed"
echo "total: $(( $(date +%s) - t0 )) s"
