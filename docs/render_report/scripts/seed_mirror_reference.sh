# Sourced by device scripts after device_env.sh: issue 18's GPU scene (the seed scene with mirror
# blocks, 1080p, 5 reflections) in M, and its converged reference in /tmp/img/ref.png: 16 / 16 spp
# x 64 frames, the plain mean (no history clamp), sample seed 1000.
M="--scene seed --scene-block mirror --size 1920x1080 --device gpu --reflections 5"
mkdir -p /tmp/img
echo "== reference 16/16 x 64 (plain mean), sample seed 1000"
timeout 200 "$B/vx" render $M --spp 16 --bounce-spp 16 --accumulate 64 --history-clamp off --sample-seed 1000 \
  --out /tmp/img/ref.png 2>&1 | grep -E "accumulated|error" | head -3
echo "# at $(( $(date +%s) - t0 )) s"
