# Sourced by device scripts after device_env.sh (stops 53-55): the scenes their calls time, at
# 1920x1080 and 4 spp, and alternated_rounds, which times binaries on scenes in alternated rounds.
#   P: the deep pond (absorption-2026-12-06/make_deep_pond.py) from above, 2 reflections;
#   S: the scattered stone and water volume of raster-transparency-2026-12-05 (D, V: device_env.sh);
#   T: the terrain of the main job (seed 1).
python3 docs/render_report/absorption-2026-12-06/make_deep_pond.py "$D/deep.raw"
P="--raw $D/deep.raw --dims 96,24,96 --type u8 --eye 48,30,8 --target 48,12,42 --size 1920x1080 --device gpu --spp 4 --reflections 2 --repeat 12"
S="--raw $D/scatter_water.raw $V --spp 4"
T="--seed 1 --size 1920x1080 --device gpu --spp 4 --repeat 12"
#   M: the scattered volume with water and glass mixed (interface-fresnel-2026-12-06/make_mixed.py,
#      stop 55): touching pairs everywhere.
python3 docs/render_report/interface-fresnel-2026-12-06/make_mixed.py "$D"
M="--raw $D/scatter_mixed.raw $V --spp 4"

# Prints each render's GPU trace median of frames 2..N, one line per round, scene and binary.
# Usage: alternated_rounds ROUNDS "BINARY..." "SCENE..." (binaries in $B, scenes named as above)
alternated_rounds() {
  for round in $(seq 1 "$1"); do
    for bin in $2; do
      for scene in $3; do
        printf "r%s %s %-7s " "$round" "$scene" "$bin"
        timeout 90 "$B/$bin" render ${!scene} --out "$D/${scene}_$bin.png" > /tmp/r.txt 2>&1
        grep "frames 2" /tmp/r.txt | sed 's/.*trace/trace/; s/, readback.*//' || tail -3 /tmp/r.txt
      done
    done
  done
}

# Runs the render tests whose names match the gtest FILTER on the NVIDIA driver with the
# validation layer (VX_TEST_DEVICE=gpu) and prints their summary.
# Usage: filtered_render_tests FILTER (vx_render_tests in $B)
filtered_render_tests() {
  LD_PRELOAD=$(ls /usr/local/nvidia/lib64/libnvidia-tls.so.* | head -1) \
    VX_TEST_DEVICE=gpu timeout 200 "$B/vx_render_tests" --gtest_brief=1 --gtest_filter="$1" 2>&1 | tail -3
}

# Renders one view and prints its GPU trace median of frames 2..N and vx render's frame-1 line on
# the see-through check (stop 57). Usage: one NAME BINARY ARGS... (BINARY in $B; the PNG to
# $D/NAME.png).
one() {
  local name=$1 bin=$2; shift 2
  printf "%-12s " "$name"
  timeout 100 "$B/$bin" render "$@" --out "$D/$name.png" > /tmp/r.txt 2>&1
  echo "$(grep "frames 2" /tmp/r.txt | sed 's/.*trace/trace/; s/, readback.*//' || tail -2 /tmp/r.txt)" \
       "$(grep -o "see-through check: [0-9]* [a-z ]*" /tmp/r.txt | head -1)"
}
