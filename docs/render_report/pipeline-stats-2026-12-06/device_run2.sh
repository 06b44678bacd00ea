#!/usr/bin/env bash
# Stop 56's second device call (as device_run.sh, .devbuild holding only vx, vx_render_tests and
# vx_cli_render_tests of 150a3f9): the pipeline report of the terrain's view (call 1 passed it
# --repeat twice and printed none), then the report's tests on the NVIDIA driver, with their
# failures in full. Not run: the session's device time was spent (docs/render_report.md).
source docs/render_report/scripts/device_env.sh > /dev/null
"$B/vx" render --seed 1 --size 1920x1080 --device gpu --spp 4 --repeat 2 --pipeline-report \
  --out /tmp/t.png > "$OUT/report.txt" 2>&1
grep -E "^pipelines|^rt pipeline|    raygen  |    hit  |executable|egister|tack|pill|ocal|^no exec" "$OUT/report.txt" |
  head -90
export LD_PRELOAD=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1)
VX_TEST_DEVICE=gpu timeout 100 "$B/vx_render_tests" --gtest_filter='PipelineReport*' > "$OUT/tests.txt" 2>&1
grep -E "^\[ |Failure|Expected|Which|kip|note" "$OUT/tests.txt" | head -30
timeout 100 "$B/vx_cli_render_tests" --gtest_filter='*PipelineReport*' > "$OUT/cli.txt" 2>&1
grep -E "^\[ |Failure|Expected|Which|error" "$OUT/cli.txt" | head -12
