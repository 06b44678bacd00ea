#!/bin/bash
# Renders one view with two `vx` binaries, for a before-and-after picture: $1 (old) writes
# ${3}_old.png and $2 (new) ${3}_new.png; the arguments after the third go to `vx render` as they
# are (the scene, the view, the samples). Prints each render's last line.
# Usage: render_old_new.sh OLD_VX NEW_VX OUT_PREFIX RENDER_ARGS...
set -eu
old=$1 new=$2 prefix=$3
shift 3
for which in old new; do
  vx=$old; [ $which = new ] && vx=$new
  "$vx" render "$@" --out "${prefix}_$which.png" | tail -1
done
