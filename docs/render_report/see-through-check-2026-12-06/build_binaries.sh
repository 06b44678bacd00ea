#!/usr/bin/env bash
# Builds what the device scripts run (from the repository root, build/release configured), stripped,
# into .devbuild/. Usage: build_binaries.sh NAME [PATCH]: vx of the tree as it is (with PATCH
# applied, then reverted) as .devbuild/NAME; NAME vx also copies vx_render_tests and
# vx_cli_render_tests. The binaries of this stop's calls:
#   vx_old  stop 56's vx (150a3f9: the trace code of 54ef25c), kept from its build_binaries.sh;
#   vx      af06ee4 in call 1 (marked pixels appended to a list; every ray's meeting counted in
#           one-dispatch frames), 434ff02 in call 2 (the pixels marked in place, the second
#           dispatch over the image; only the view rays' first walks counted).
set -euo pipefail
name=$1 patch=${2:-}
mkdir -p .devbuild
[ -n "$patch" ] && git apply "$patch"
ninja -C build/release tools/vx tests/render/vx_render_tests tests/tools/vx_cli_render_tests > /dev/null
strip -o ".devbuild/$name" build/release/tools/vx
if [ "$name" = vx ]; then
  strip -o .devbuild/vx_render_tests build/release/tests/render/vx_render_tests
  strip -o .devbuild/vx_cli_render_tests build/release/tests/tools/vx_cli_render_tests
fi
[ -n "$patch" ] && git apply -R "$patch"
ninja -C build/release tools/vx tests/render/vx_render_tests tests/tools/vx_cli_render_tests > /dev/null
md5sum .devbuild/*
