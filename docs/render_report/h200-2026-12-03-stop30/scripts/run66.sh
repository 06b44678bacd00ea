#!/bin/bash
# Device call 66 (stop 30): Table 6.3 at equal error on glazed blocks again, with this stop's
# final build (the later passes launched over every pixel, as at stop 29; samples by weight^0.8
# among the candidates), to see the pick of call 65 hold in a second run.
source "$(dirname "$0")/device_env.sh"
t0=$(date +%s)
mkdir -p $OUT/glazed
timeout 400 stdbuf -oL .devbuild/new/vx bench render --scene seed --scene-block glazed --size 1920x1080 --reference-spp 256 --repeat 10 --device gpu --lighting thesis --sections equal-error --split-hits 5 --out $OUT/glazed > $OUT/glazed/log.txt 2>&1
echo "glazed: rc $? $(( $(date +%s) - t0 )) s"
grep -E " +\| | target |RT flat|frames rendered|by weight" $OUT/glazed/log.txt | tail -40
