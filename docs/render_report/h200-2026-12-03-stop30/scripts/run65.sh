#!/bin/bash
# Device call 65 (stop 30): the later passes launched over their lists (vkCmdTraceRaysIndirectKHR,
# this build, .devbuild/new) against stop 29's launch over every pixel (fd50632, .devbuild/old),
# side by side, and samples by weight^0.8; then Table 6.3 at equal error on glazed blocks.
source "$(dirname "$0")/device_env.sh"
.devbuild/new/vx info | grep -E "\[|vulkan"
A="--scene seed --scene-block glazed --size 1920x1080 --device gpu --lighting thesis --repeat 30 --reflections 5"
t0=$(date +%s)
run() { # name, variants ("bin split" ...), config
  local name=$1 variants=$2; shift 2
  for v in $variants; do
    local b=${v%:*} k=${v#*:}
    echo "== $name $b split=$k"
    local bin=.devbuild/$b/vx
    timeout 60 $bin render $A "$@" --split-hits $k --out /tmp/${name}_${b}_$k.png 2>&1 | grep -E "frames 2\.\.|rror"
  done
  md5sum /tmp/${name}_*.png | awk '{print $1}' | sort -u | wc -l | awk '{print "  distinct images:", $1}'
}
run w56 "new:0 old:5 new:5 old:5 new:5" --spp 56 --samples-by weight
run c25_25 "old:5 new:5 old:5 new:5" --spp 25 --bounce-spp 25
run c1_1 "old:5 new:5 old:5 new:5" --spp 1 --bounce-spp 1
for n in 40 44 48; do
  run e08_$n "new:0 new:5" --spp $n --samples-by weight --weight-exponent 0.8
done
echo "pairs: $(( $(date +%s) - t0 )) s"
mkdir -p $OUT/glazed
timeout 330 stdbuf -oL .devbuild/new/vx bench render --scene seed --scene-block glazed --size 1920x1080 --reference-spp 256 --repeat 10 --device gpu --lighting thesis --sections equal-error --split-hits 5 --out $OUT/glazed > $OUT/glazed/log.txt 2>&1
echo "glazed: rc $? $(( $(date +%s) - t0 )) s"
grep -E " +\| | target |RT flat|frames rendered" $OUT/glazed/log.txt | tail -40
