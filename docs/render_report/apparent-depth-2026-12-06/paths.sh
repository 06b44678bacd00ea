#!/bin/bash
# Stop 54 (2026-12-06), tried, not kept: the denoiser's depth guide of a hit seen through water.
# Builds three binaries from apparent_depth.patch (APPARENT_MODE 0: the bent path's length, as
# main; 1: each segment over its medium's index, the sagittal image, l / n; 2: the tangential
# image, l cos^2(theta_i) / (n cos^2(theta_t))) and runs the camera paths of `vx bench render`
# on the deep pond (absorption-2026-12-06/make_deep_pond.py), lavapipe, 128x72, 24 frames per
# path, 64-spp references per pose.
# Usage (repository root, a configured build/release, a clean tree): bash <this file>
set -eu
HERE=docs/render_report/apparent-depth-2026-12-06
python3 docs/render_report/absorption-2026-12-06/make_deep_pond.py /tmp/deep.raw
git apply $HERE/apparent_depth.patch
trap 'git checkout -- shaders; (cd build/release && ninja tools/vx > /dev/null)' EXIT
for m in 0 1 2; do
  sed -i "s/^#define APPARENT_MODE [0-9]/#define APPARENT_MODE $m/" shaders/shared/raygen_common.glsl
  (cd build/release && ninja tools/vx > /dev/null)
  mkdir -p /tmp/ap$m
  build/release/tools/vx bench render --raw /tmp/deep.raw --dims 96,24,96 --size 128x72 --sections paths \
    --path-frames 24 --path-reference-spp 64 --out /tmp/ap$m | grep "|" | grep -v edit | sed "s/^/mode $m /"
done
