#!/bin/bash
# Device call 2 (2026-12-06, stop 52): what the variant without see-through code gains where no
# see-through block is drawn. Binaries: vx_51 (cfd014f), vx_fresnel (cc940c0: water and glass
# surfaces that mirror) and vx (5c250db: the variant). GPU trace medians of frames 2..12, three
# alternated rounds, on the seed mirror scene at issue 18's one-frame settings; its images come back
# to compare here (scripts/compare_png.py). Then the render test programs with the validation
# layer (VX_TEST_DEVICE=gpu), this stop's code.
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
source docs/render_report/scripts/device_env.sh
M="--scene seed --scene-block mirror --size 1920x1080 --device gpu --reflections 5 --split-hits 5 --spp 4 --bounce-spp 4 --denoise on --repeat 12"
for round in 1 2 3; do
  for bin in vx_51 vx_fresnel vx; do
    printf "round %s seed_mirror %-10s " $round $bin
    timeout 60 $B/$bin render $M --out "$D/seed_$bin.png" > /tmp/r.txt 2>&1; grep "frames 2" /tmp/r.txt || tail -3 /tmp/r.txt
  done
  echo "elapsed $(( $(date +%s) - t0 )) s"
done
for bin in vx_fresnel vx; do
  cmp -s "$D/seed_$bin.png" "$D/seed_vx_51.png" && echo "seed: $bin and vx_51 identical" || echo "seed: $bin and vx_51 differ"
done
cp "$D"/seed_vx_51.png "$D"/seed_vx_fresnel.png "$D"/seed_vx.png $OUT/
bash docs/render_report/touching-pairs-2026-12-05/device_suites.sh # The render suites, validation on.
echo "total: $(( $(date +%s) - t0 )) s"
