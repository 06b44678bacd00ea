#!/usr/bin/env bash
# Stop 67's lavapipe figure: issue 18's one frame (4 / 4 denoised, light cache, 2 a-trous passes)
# against 25 / 25 raw, each run one process interleaving the two (`vx render --versus-raw 25`,
# 30 pairs); builds alternated run by run. One line per run: label, the median of the pairs'
# wall-time ratios, its quartiles, and the frames' wall medians.
# Usage: versus.sh ROUNDS SCENE.raw label=VX ...   (SCENE.raw: scripts/measure_one_frame.py's
# scene(), as timing.sh in ../denoise-passes-2026-12-07 says).
rounds=$1 raw=$2
shift 2
view="--raw $raw --dims 48,16,48 --eye 42,6,20 --target 22,2,0 --size 112x72 --reflections 4"
frame="--spp 4 --bounce-spp 4 --denoise on --light-cache on --denoise-passes 2 --repeat 30 --versus-raw 25"
for _ in $(seq "$rounds"); do
  for c in "$@"; do
    # shellcheck disable=SC2086 # view and frame are lists of arguments.
    line=$("${c#*=}" render $view $frame --out /tmp/vx_versus.png 2>&1 | grep 'versus 25 spp raw')
    ratio=$(echo "$line" | grep -oE '[0-9.]+x less time' | cut -dx -f1)
    quartiles=$(echo "$line" | grep -oE 'quartiles [0-9.]+-[0-9.]+' | cut -d' ' -f2)
    frames=$(echo "$line" | grep -oE 'frame [0-9.]+ ms against [0-9.]+' | cut -d' ' -f2,5)
    echo "${c%%=*} $ratio $quartiles $frames"
  done
done
