# Sourced by the device scripts that time --split-hits side by side (stop 29's run61.sh, stop 30's
# run68.sh). run NAME "SPLITS" ARGS...: `$V ARGS --split-hits K` for each K of SPLITS in turn (V:
# the vx render command before its arguments; each run cut after ${TIMEOUT:-60} s), printing its
# GPU medians line, then how many distinct images the runs of NAME wrote (1: the same image).
run() {
  local name=$1 splits=$2; shift 2
  for k in $splits; do
    echo "== $name split=$k"
    timeout ${TIMEOUT:-60} $V "$@" --split-hits $k --out /tmp/${name}_$k.png 2>&1 | grep -E "frames 2\.\.|rror"
  done
  md5sum /tmp/${name}_*.png | awk '{print $1}' | sort -u | wc -l | awk '{print "  distinct images:", $1}'
}
