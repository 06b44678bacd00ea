#!/bin/bash
# Device call 5 (2026-12-06, stop 55): sky rays from under water bent where they leave it
# (kWalkSky: Snell's window). Binaries: vx_dead (3e14aba) and vx_sky (1c7865b). Scenes P, S, T
# as device_run.sh's; three alternated rounds; then the render tests of see-through blocks, the
# sun and the sky with the validation layer (VX_TEST_DEVICE=gpu), built at 1c7865b.
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
source docs/render_report/scripts/device_env.sh
source docs/render_report/scripts/device_scenes.sh
alternated_rounds 3 "vx_dead vx_sky" "P S T" 2>&1 | tee $OUT/rounds.log
(cd $D && md5sum *.png | sort) | tee $OUT/md5.log
export LD_PRELOAD=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1) # Static TLS: render_report.md.
VX_TEST_DEVICE=gpu timeout 200 $B/vx_render_tests --gtest_brief=1 \
  --gtest_filter='*Sun*:*Pool*:*Water*:*Lake*:*Interface*:*OneIndex*:*Transparen*:*Glass*:*Sky*' 2>&1 | tail -3
echo "total: $(( $(date +%s) - t0 )) s"
