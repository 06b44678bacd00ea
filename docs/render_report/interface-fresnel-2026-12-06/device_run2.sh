#!/bin/bash
# Device call 2 (2026-12-06, stop 55). Call 1 (device_run.sh) found the pairing's first version
# slower also where nothing pairs (S +4.9%, P +2.6%, T +1.4%): its shadow rays cleared and read
# the payload's slots and its sky rays' walk read both media's indices at every face. Now both
# only in the probing variant or where the probe found a partner. Binaries: vx_base (main at
# 0bce48b), vx (this stop, two slots) and vx_s1 (one slot: fewer payload bytes, pairs lost where
# another marked face comes between). Scenes as device_run.sh's; three alternated rounds.
# (Since the call, scene M comes from scripts/device_scenes.sh: the same renders.)
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
source docs/render_report/scripts/device_env.sh
source docs/render_report/scripts/device_scenes.sh
alternated_rounds 3 "vx_base vx vx_s1" "P S T M" 2>&1 | tee $OUT/rounds.log
(cd $D && md5sum *.png | sort) | tee $OUT/md5.log
cp $D/M_vx.png $D/M_vx_s1.png $OUT/ 2>/dev/null
echo "total: $(( $(date +%s) - t0 )) s"
