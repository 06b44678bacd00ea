#!/bin/bash
# Device call 68 (stop 30): what the split into passes (--split-hits, the same images) does where
# stop 29 did not measure it with the lists: terrain at the sandbox's recommended settings (8 spp,
# 1 per bounce, 2 bounces, denoised) and at vx render's defaults; the seed mirror scene's
# one-frame configurations at the default lighting (issue 18's one-frame target: 4 / 4 denoised
# against 25 / 25 raw). Alternating, GPU trace medians of frames 2-30.
source "$(dirname "$0")/device_env.sh"
T="--seed 1 --radius 6 --size 1920x1080 --device gpu --repeat 30"
M="--scene seed --scene-block mirror --size 1920x1080 --device gpu --repeat 30 --reflections 5"
t0=$(date +%s)
V=".devbuild/new/vx render" TIMEOUT=90
source "$(dirname "$0")/../../scripts/split_pairs.sh" # run NAME "SPLITS" ARGS...
run terrain_sandbox "0 2 0 2" $T --spp 8 --bounce-spp 1 --denoise on
run terrain_default "0 2 0 2" $T
run mirror_4_4_denoised "0 5 0 5" $M --spp 4 --bounce-spp 4 --denoise on
run mirror_25_25 "0 5 0 5" $M --spp 25 --bounce-spp 25
echo "total: $(( $(date +%s) - t0 )) s"
