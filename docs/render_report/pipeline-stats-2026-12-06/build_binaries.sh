#!/usr/bin/env bash
# Builds the binaries device_run.sh times (run here, from the repository root, on a clean tree of
# the stop's code with build/release configured): vx as the tree is, and one vx per patch in this
# folder, each applied, built and reverted in turn. Stripped, into .devbuild/.
set -euo pipefail
dir=docs/render_report/pipeline-stats-2026-12-06
mkdir -p .devbuild
build() { ninja -C build/release tools/vx tests/render/vx_render_tests tests/tools/vx_cli_render_tests > /dev/null; }
build
strip -o .devbuild/vx build/release/tools/vx
strip -o .devbuild/vx_render_tests build/release/tests/render/vx_render_tests
strip -o .devbuild/vx_cli_render_tests build/release/tests/tools/vx_cli_render_tests
for pair in nosurf:experiment_no_surface none:experiment_no_see_through_code early:pick_before_light \
            mem:surface_in_memory; do
  git apply "$dir/${pair#*:}.patch"
  build
  strip -o ".devbuild/vx_${pair%%:*}" build/release/tools/vx
  git apply -R "$dir/${pair#*:}.patch"
done
build
md5sum .devbuild/*
