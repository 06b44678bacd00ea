#!/bin/bash
# Device call 2 (2026-12-06, stop 54): call 1 found the precomputed optics no faster on the
# scattered water, 1% faster on the terrain and 1.8% slower on the deep pond. Is the table's larger
# element (48 bytes, was 32) the cause? Binaries: vx (f6d1a0e, per-ray optics), vx_mt (0173ae4:
# vec4 optics, 48-byte elements), vx_mt64 (0173ae4 padded to 64-byte elements) and vx_e (32-byte
# elements: the index in emission.w, which was the see-through flag 1, and sigma = -ln(albedo) per
# ray as before). GPU trace medians, three alternated rounds, the scenes of device_run.sh.
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
source docs/render_report/scripts/device_env.sh
python3 docs/render_report/absorption-2026-12-06/make_deep_pond.py "$D/deep.raw"
P="--raw $D/deep.raw --dims 96,24,96 --type u8 --eye 48,30,8 --target 48,12,42 --size 1920x1080 --device gpu --spp 4 --reflections 2 --repeat 12"
S="--raw $D/scatter_water.raw $V --spp 4"
T="--seed 1 --size 1920x1080 --device gpu --spp 4 --repeat 12"
for round in 1 2 3; do
  for bin in vx vx_mt vx_mt64 vx_e; do
    for scene in P S T; do
      printf "round %s %s %-7s " $round $scene $bin
      timeout 90 $B/$bin render ${!scene} --out "$D/${scene}_$bin.png" > /tmp/r.txt 2>&1; grep "frames 2" /tmp/r.txt | sed 's/, readback.*//' || tail -3 /tmp/r.txt
    done
  done
  echo "elapsed $(( $(date +%s) - t0 )) s"
done
(cd $D && md5sum *.png)
echo "total: $(( $(date +%s) - t0 )) s"
