#!/bin/bash
# Device call 61 (stop 29): hits in passes of their own (RenderSettings::split_hits 0, 1, 2, 3, 5),
# side by side: vx render GPU medians of 30 frames, thesis's glazed seed scene at 1080p, 5
# reflections, and the images' checksums (the same image).
source "$(dirname "$0")/device_env.sh"
V=".devbuild/new/vx render --scene seed --scene-block glazed --size 1920x1080 --device gpu --lighting thesis --repeat 30 --reflections 5"
t0=$(date +%s)
source "$(dirname "$0")/../../scripts/split_pairs.sh" # run NAME "SPLITS" ARGS...
run w56 "0 1 2 3 5" --spp 56 --samples-by weight
run w40 "0 1 2 3 5" --spp 40 --samples-by weight
run w48 "5 3 2 1" --spp 48 --samples-by weight
run c25_4 "0 1 2 3 5" --spp 25 --bounce-spp 4
run c25_25 "0 1 2 5" --spp 25 --bounce-spp 25
run c4_4 "0 1 2 5" --spp 4 --bounce-spp 4
run c1_1 "0 1 2 5" --spp 1 --bounce-spp 1
run w56_again "5 3 2 1 0" --spp 56 --samples-by weight
echo "total $(( $(date +%s) - t0 )) s"
