#!/usr/bin/env bash
# Stop 57's device call: the see-through check (RenderSettings::see_through_check) against one
# dispatch, side by side in one call. Binaries from build_binaries.sh (vx_old: stop 56's code).
# Scenes (device_scenes.sh): T terrain seed 1, P the deep pond from above, S scattered water, M
# water and glass mixed; 1920x1080, 4 spp. Each round runs every binary and setting once.
source docs/render_report/scripts/device_env.sh > /dev/null
source docs/render_report/scripts/device_scenes.sh
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
for round in 1 2 3; do
  echo "# round $round"
  for sc in T P S M; do
    [ "$round" = 3 ] && [ "$sc" != T ] && continue
    one "${sc}_old" vx_old ${!sc}
    one "${sc}_off" vx ${!sc} --see-through-check off
    one "${sc}_on" vx ${!sc}
    one "${sc}_all" vx ${!sc} --see-through-check-share 1
  done
  echo "# at $(( $(date +%s) - t0 )) s"
done
echo "# md5 of each render's PNG"
(cd "$D" && md5sum *.png | sort)
echo "# the check's render tests on the NVIDIA driver"
filtered_render_tests '*SeeThroughCheck*:*ShadowRaysThroughGlassAlone*:*WithoutSeeThroughBlocks*:*Transparent*'
echo "# the pipeline report of T (stacks; statistics where listed)"
"$B/vx" render --seed 1 --size 1920x1080 --device gpu --spp 4 --repeat 2 --pipeline-report \
  --out /tmp/t.png > "$OUT/report.txt" 2>&1
grep -E "^pipelines|^rt pipeline|    raygen  |    hit  |executable|egister|tack|pill|^no exec|note" \
  "$OUT/report.txt" | head -60
echo "# at $(( $(date +%s) - t0 )) s"
