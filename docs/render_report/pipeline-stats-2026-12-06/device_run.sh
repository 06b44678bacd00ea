#!/usr/bin/env bash
# Stop 56's device call (run from the repository root on the lent GPU machine, .gl, .devlibs and
# .devbuild carried; build_binaries.sh makes .devbuild here): the pipeline report of every variant
# on the NVIDIA driver, then the terrain (T) timed with five binaries in alternated rounds, the
# pond (P) and the scattered water (S) with three:
#   vx         the stop's code (the renderer as at stop 55's eb223cb, plus the report);
#   vx_nosurf  experiment_no_surface.patch: no water or glass surface is ever followed, so the
#              walk's surface (g_surface) is dead after each walk;
#   vx_none    experiment_no_see_through_code.patch: kSeeThrough specialised false in every
#              variant, the see-through code's cost (water drawn as opaque where it is met);
#   vx_early   pick_before_light.patch: the path's next ray picked before the hit's light is
#              sampled, so only the picked ray's state stays live across the light's traces;
#   vx_mem     surface_in_memory.patch: the walk's surface written to a per-pixel buffer (48
#              bytes) where there is one and read back after the light's traces, so only a flag
#              stays live across them.
# vx_early and vx_mem render the same images as vx on lavapipe (the pond, the scattered water and
# the terrain, md5 of the PNGs). Then the report's tests on the NVIDIA driver. Logs go to $OUT.
source docs/render_report/scripts/device_env.sh
source docs/render_report/scripts/device_scenes.sh
for bin in vx; do
  "$B/$bin" render $T --repeat 2 --pipeline-report --out "$D/t_report.png" > "$OUT/report_T_$bin.txt" 2>&1
  grep -A2000 "^pipelines on" "$OUT/report_T_$bin.txt" |
    grep -E "^rt pipeline|    raygen  |executable|egister|pill|ocal|tack|ize" | head -150
done
alternated_rounds 3 "vx vx_nosurf vx_none vx_early vx_mem" "T" 2>&1 | tee "$OUT/rounds.txt"
alternated_rounds 3 "vx vx_early vx_mem" "P" 2>&1 | tee -a "$OUT/rounds.txt"
alternated_rounds 2 "vx vx_early vx_mem" "S" 2>&1 | tee -a "$OUT/rounds.txt"
md5sum "$D"/*.png | tee "$OUT/md5.txt"
filtered_render_tests 'PipelineReport*' | tee "$OUT/tests.txt"
LD_PRELOAD=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1) VX_TEST_DEVICE=gpu \
  timeout 100 "$B/vx_cli_render_tests" --gtest_brief=1 --gtest_filter='*PipelineReport*' 2>&1 | tail -3
echo "elapsed $(( $(date +%s) - t0 )) s"
