#!/bin/bash
# Device call 71 (2026-12-05): run70.sh's Table 6.3 bench again, alone, with time to finish
# (run70's 230 s limit cut it off). The same set-up as run70.sh.
set -u; for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
mkdir -p /tmp/dl && tar xzf .devlibs/libs.tgz -C /tmp/dl
export LD_LIBRARY_PATH=/tmp/dl/lib VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
timeout 520 .devbuild/vx bench render --scene seed --scene-block glazed --size 1920x1080 --reference-spp 256 \
  --repeat 10 --device gpu --lighting thesis --sections equal-error --split-hits 5 --out /tmp/eq > $OUT/eq.log 2>&1
cp /tmp/eq/*.csv /tmp/eq/*.md $OUT/
