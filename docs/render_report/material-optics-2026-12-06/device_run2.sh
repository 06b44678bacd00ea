#!/bin/bash
# Device call 2 (2026-12-06, stop 54): call 1 found the precomputed optics no faster on the
# scattered water, 1% faster on the terrain and 1.8% slower on the deep pond. Is the table's larger
# element (48 bytes, was 32) the cause? Binaries: vx (f6d1a0e, per-ray optics), vx_mt (0173ae4:
# vec4 optics, 48-byte elements), vx_mt64 (0173ae4 padded to 64-byte elements) and vx_e (32-byte
# elements: the index in emission.w, which was the see-through flag 1, and sigma = -ln(albedo) per
# ray as before). GPU trace medians, three alternated rounds, the scenes of device_run.sh.
# Usage (device, repository root, .gl .devlibs .devbuild carried): bash <this file>
# (Since the call, the scenes and the loop come from scripts/device_scenes.sh: the same renders.)
source docs/render_report/scripts/device_env.sh
source docs/render_report/scripts/device_scenes.sh
alternated_rounds 3 "vx vx_mt vx_mt64 vx_e" "P S T"
(cd $D && md5sum *.png)
echo "total: $(( $(date +%s) - t0 )) s"
