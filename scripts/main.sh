#!/usr/bin/env bash
# The main job: set up (installs what is missing), build, run vx on the seed scene, and render
# the default terrain world to out/vx_default.png (its trace takes about 6 s on lavapipe here).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh release
./build/release/tools/vx info
./build/release/tools/vx mesh --scene seed
mkdir -p out
./build/release/tools/vx render --seed 1 --size 640x360 --out out/vx_default.png
