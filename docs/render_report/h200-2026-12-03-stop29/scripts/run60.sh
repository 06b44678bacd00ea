#!/bin/bash
# Device call 60 (stop 29): rays traced inline (ray queries) against the pipeline's shader calls,
# side by side: VX_RAY_QUERY=0 (pipeline), 1 (shadow rays inline), 2 (every ray inline). vx render
# GPU medians of 30 frames, thesis's glazed seed scene at 1080p, and the images' checksums.
source "$(dirname "$0")/device_env.sh"
V=".devbuild/new/vx render --scene seed --scene-block glazed --size 1920x1080 --device gpu --lighting thesis --repeat 30"
t0=$(date +%s)
echo "== flat"; timeout 60 $V --shading flat --reflections 0 --spp 1 --out /tmp/flat.png 2>&1 | grep -E "device:|frames 2\.\.|rror"
i=0
run() { # name, order, config
  local name=$1 order=$2; shift 2
  for rq in $order; do
    echo "== $name rq=$rq"
    VX_RAY_QUERY=$rq timeout 60 $V "$@" --out /tmp/${name}_$rq.png 2>&1 | grep -E "frames 2\.\.|rror"
  done
  md5sum /tmp/${name}_*.png | awk '{print $1}' | sort -u | wc -l | awk '{print "  distinct images:", $1}'
}
run s56on "0 1 2" --reflections 5 --spp 56 --samples-by weight --first-hit-pass on
run s56off "0 1 2" --reflections 5 --spp 56 --samples-by weight
run s25 "0 1 2" --reflections 0 --spp 25
run r25_1 "0 1 2" --reflections 5 --spp 25 --bounce-spp 1 --first-hit-pass on
run r1_1 "0 1 2" --reflections 5 --spp 1 --bounce-spp 1
run s56on_again "2 1 0" --reflections 5 --spp 56 --samples-by weight --first-hit-pass on
T=".devbuild/new/vx render --seed 1 --radius 6 --size 1920x1080 --device gpu --repeat 30"
for rq in 0 1 2; do echo "== terrain default rq=$rq"; VX_RAY_QUERY=$rq timeout 90 $T --out /tmp/t_$rq.png 2>&1 | grep -E "frames 2\.\.|rror"; done
md5sum /tmp/t_*.png | awk '{print $1}' | sort -u | wc -l | awk '{print "  distinct images:", $1}'
echo "total $(( $(date +%s) - t0 )) s"
