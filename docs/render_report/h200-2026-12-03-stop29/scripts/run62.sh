#!/bin/bash
# Device call 62 (stop 29): Table 6.3 at equal error (thesis's lighting, seed scene, glazed and
# mirror blocks) with every hit in a pass of its own (--split-hits 5: the same images, call 61).
source "$(dirname "$0")/device_env.sh"
for b in glazed mirror; do
  mkdir -p $OUT/$b
  t0=$(date +%s)
  timeout 270 stdbuf -oL .devbuild/new/vx bench render --scene seed --scene-block $b --size 1920x1080 --reference-spp 256 --repeat 10 --device gpu --lighting thesis --sections equal-error --split-hits 5 --out $OUT/$b > $OUT/$b/log.txt 2>&1
  echo "$b: rc $? $(( $(date +%s) - t0 )) s"
  grep -E " +\| | target |RT flat|frames rendered" $OUT/$b/log.txt | tail -30
done
