#!/bin/bash
# Device call 63 (stop 29): later passes over a list of the live paths (this build, .devbuild/new)
# against the same passes over every pixel (call 61-62's build, .devbuild/old/vx_split_flag), side
# by side; then Table 6.3 at equal error on glazed blocks with --split-hits 5 (this build).
source "$(dirname "$0")/device_env.sh"
A="--scene seed --scene-block glazed --size 1920x1080 --device gpu --lighting thesis --repeat 30 --reflections 5"
t0=$(date +%s)
run() { # name, config
  local name=$1; shift
  for v in "new 0" "old 5" "new 5" "new 3"; do
    set -- $v "$@"; local b=$1 k=$2; shift 2
    echo "== $name $b split=$k"
    local bin=.devbuild/new/vx; [ $b = old ] && bin=.devbuild/old/vx_split_flag
    timeout 60 $bin render $A "$@" --split-hits $k --out /tmp/${name}_${b}_$k.png 2>&1 | grep -E "frames 2\.\.|rror"
  done
  md5sum /tmp/${name}_*.png | awk '{print $1}' | sort -u | wc -l | awk '{print "  distinct images:", $1}'
}
run w56 --spp 56 --samples-by weight
run w52 --spp 52 --samples-by weight
run c1_1 --spp 1 --bounce-spp 1
run c25_4 --spp 25 --bounce-spp 4
run c25_25 --spp 25 --bounce-spp 25
echo "pairs: $(( $(date +%s) - t0 )) s"
mkdir -p $OUT/glazed
timeout 300 .devbuild/new/vx bench render --scene seed --scene-block glazed --size 1920x1080 --reference-spp 256 --repeat 10 --device gpu --lighting thesis --sections equal-error --split-hits 5 --out $OUT/glazed > $OUT/glazed/log.txt 2>&1
echo "glazed: rc $? $(( $(date +%s) - t0 )) s"
grep -E " +\| | target |RT flat|frames rendered" $OUT/glazed/log.txt | tail -12
