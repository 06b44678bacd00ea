#!/usr/bin/env bash
# Stop 65's lavapipe frame times: alternated rounds of `vx render --repeat 15` on issue 18's
# hidden-style scene; one line per run: label, trace ms, denoiser ms, frame ms (wall), medians of
# frames 2..15. Usage: timing.sh ROUNDS SCENE.raw 'label=VX:args' ...
# SCENE.raw: scripts/measure_one_frame.py's scene() (python3 -c "import sys;
# sys.path.insert(0, 'scripts'); import measure_one_frame as m; m.scene('/tmp/hidden.raw')").
# Example: timing.sh 10 /tmp/hidden.raw "p2=build/release/tools/vx:--spp 4 --bounce-spp 4 --denoise on
#   --light-cache on --denoise-passes 2" "raw25=build/release/tools/vx:--spp 25 --bounce-spp 25"
rounds=$1 raw=$2
shift 2
view="--raw $raw --dims 48,16,48 --eye 42,6,20 --target 22,2,0 --size 112x72 --reflections 4 --repeat 15"
for _ in $(seq "$rounds"); do
  for c in "$@"; do
    label=${c%%=*} rest=${c#*=}
    vx=${rest%%:*} extra=${rest#*:}
    # shellcheck disable=SC2086 # extra is a list of arguments.
    line=$("$vx" render $view $extra --out /tmp/vx_timing.png 2>&1 | grep 'frames 2')
    num() { echo "$line" | grep -o "$1 [0-9.]*" | head -1 | cut -d' ' -f2; }
    echo "$label $(num trace) $(num denoiser) $(echo "$line" | grep -o 'frame [0-9.]* ms wall' | cut -d' ' -f2)"
  done
done
