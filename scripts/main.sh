#!/usr/bin/env bash
# The main job: set up (installs what is missing), build, and run vx on the seed scene.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh release
./build/release/tools/vx info
./build/release/tools/vx mesh --scene seed
