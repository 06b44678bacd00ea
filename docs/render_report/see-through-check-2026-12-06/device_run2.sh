#!/usr/bin/env bash
# Stop 57's second device call (binaries: build_binaries.sh; cut to fit the session's last device
# time: no tests). Call 1 found af06ee4's one-dispatch frames 3% slower than stop 56's (vx_old) and its
# checked frames of S and M not byte-identical to one dispatch, nor to each other. This call times
# the final code (vx: the pixels marked, only the view rays' first walks counted in the
# see-through variant) against stop 56's, and renders S and M checked twice to see whether their
# images still vary from run to run, or differ from one dispatch's.
source docs/render_report/scripts/device_env.sh > /dev/null
source docs/render_report/scripts/device_scenes.sh
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
for round in 1 2; do
  echo "# round $round"
  one T_old vx_old $T; one T_off vx $T --see-through-check off; one T_on vx $T
  [ "$round" = 1 ] && { one P_old vx_old $P; one P_off vx $P --see-through-check off; one P_on vx $P; }
  echo "# at $(( $(date +%s) - t0 )) s"
done
S1="--raw $D/scatter_water.raw --dims 256,48,256 --type u8 --eye 128,70,-60 --target 128,20,128 --device gpu --size 1920x1080 --spp 4"
M1="--raw $D/scatter_mixed.raw --dims 256,48,256 --type u8 --eye 128,70,-60 --target 128,20,128 --device gpu --size 1920x1080 --spp 4"
for sc in S1 M1; do
  one "${sc}_off" vx ${!sc} --see-through-check off
  one "${sc}_all_1" vx ${!sc} --see-through-check-share 1
  one "${sc}_all_2" vx ${!sc} --see-through-check-share 1
done
echo "# md5 of each render's PNG"
(cd "$D" && md5sum *.png | sort)
echo "# at $(( $(date +%s) - t0 )) s"
