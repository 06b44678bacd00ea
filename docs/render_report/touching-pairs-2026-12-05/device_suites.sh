#!/bin/bash
# Device call (2026-12-05, stop 50): the render test programs on the NVIDIA driver with the
# validation layer (VX_TEST_DEVICE=gpu), this stop's code. Carry .gl, .devlibs and .devbuild
# (vx, vx_render_tests, vx_cli_render_tests, vx_engine_render_tests).
# Usage (device, repository root): bash <this file>
source docs/render_report/scripts/device_env.sh
export LD_PRELOAD=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1) # Static TLS: render_report.md.
for t in vx_render_tests vx_cli_render_tests vx_engine_render_tests; do
  echo "== $t"
  VX_TEST_DEVICE=gpu timeout 400 $B/$t --gtest_brief=1 > $OUT/$t.log 2>&1; echo "rc=$?"
  grep -E "FAILED|PASSED|tests ran|VUID|SKIPPED|Skipped" -A1 $OUT/$t.log | head -30
  echo "elapsed $(( $(date +%s) - t0 )) s"
done
