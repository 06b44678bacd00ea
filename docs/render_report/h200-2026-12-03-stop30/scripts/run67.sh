#!/bin/bash
# Device call 67 (stop 30): Table 6.3 at equal error on mirror blocks with every hit in a pass of
# its own and the lists (this stop's final build; call 62 ran the passes over every pixel).
source "$(dirname "$0")/device_env.sh"
t0=$(date +%s)
mkdir -p $OUT/mirror
timeout 400 stdbuf -oL .devbuild/new/vx bench render --scene seed --scene-block mirror --size 1920x1080 --reference-spp 256 --repeat 10 --device gpu --lighting thesis --sections equal-error --split-hits 5 --out $OUT/mirror > $OUT/mirror/log.txt 2>&1
echo "mirror: rc $? $(( $(date +%s) - t0 )) s"
grep -E " +\| | target |RT flat|frames rendered|by weight" $OUT/mirror/log.txt | tail -40
