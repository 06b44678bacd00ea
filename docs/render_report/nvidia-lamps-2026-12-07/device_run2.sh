#!/usr/bin/env bash
# Stop 63's second device call, not run: no machine came in four tries. Run from the repository
# root on the lent GPU machine, .gl, .devlibs and .devbuild carried: the render test programs
# other than vx_render_tests (which call 2 ran whole) on the NVIDIA driver with the validation
# layer, built from e3b9698 (the finite lights' loop unrolled): .devbuild holds vx (the CLI
# tests' VX_BINARY, copied into place by device_env.sh), vx_cli_render_tests,
# vx_engine_render_tests and vx_facade_render_tests.
source docs/render_report/scripts/device_env.sh
pre=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1)
for bin in vx_cli_render_tests vx_engine_render_tests vx_facade_render_tests; do
  echo "# $bin"
  LD_PRELOAD=$pre VX_TEST_DEVICE=gpu timeout 240 "$B/$bin" --gtest_brief=1 2>&1 |
    grep -E "FAILED|PASSED|SKIPPED|tests ran|Failure|Which is|skip" | head -20
  echo "# at $(( $(date +%s) - t0 )) s"
done
