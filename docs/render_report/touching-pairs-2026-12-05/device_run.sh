#!/bin/bash
# Device call (2026-12-05, stop 50): the probing pipeline variant only where two different
# transparent blocks touch (render/touching_pairs.h). Binaries: vx_base (main at a8eae06: the
# variant whenever the marked faces hold two kinds, so glass and water anywhere on chunk borders)
# and vx (this stop). Volumes: water_glass (make_volume.py: glass and water on border planes,
# none touching: vx_base probes, vx does not) and scatter_water (no glass: neither probes, a
# control for the two binaries). GPU trace medians of frames 2..20, three alternated rounds.
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
source docs/render_report/scripts/device_env.sh
python3 docs/render_report/touching-pairs-2026-12-05/make_volume.py "$D"
$B/vx info 2>&1 | tail -2
for round in 1 2 3; do
  for vol in water_glass scatter_water; do
    for bin in vx_base vx; do
      printf "round %s %-13s %-8s " $round $vol $bin
      timeout 60 $B/$bin render --raw "$D/$vol.raw" $V --spp 4 --reflections 2 --out "$D/${vol}_$bin.png" > /tmp/r.txt 2>&1
      grep "frames 2" /tmp/r.txt; grep -c "coincident-face probe" /tmp/r.txt
    done
  done
  echo "elapsed $(( $(date +%s) - t0 )) s"
done
for vol in water_glass scatter_water; do
  cmp "$D/${vol}_vx.png" "$D/${vol}_vx_base.png" && echo "$vol: vx and vx_base identical"
done
cp "$D"/water_glass_vx.png $OUT/ 2>/dev/null
echo "total: $(( $(date +%s) - t0 )) s"
