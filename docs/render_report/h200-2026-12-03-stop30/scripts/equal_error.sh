#!/bin/bash
# Table 6.3 at equal error on the seed scene of blocks $1 (glazed or mirror) with every hit in a
# pass of its own (--split-hits 5), as device calls 66 and 67 ran it (each a line calling this).
source "$(dirname "$0")/device_env.sh"
b=$1
t0=$(date +%s)
mkdir -p $OUT/$b
timeout 400 stdbuf -oL .devbuild/new/vx bench render --scene seed --scene-block $b --size 1920x1080 --reference-spp 256 --repeat 10 --device gpu --lighting thesis --sections equal-error --split-hits 5 --out $OUT/$b > $OUT/$b/log.txt 2>&1
echo "$b: rc $? $(( $(date +%s) - t0 )) s"
grep -E " +\| | target |RT flat|frames rendered|by weight" $OUT/$b/log.txt | tail -40
