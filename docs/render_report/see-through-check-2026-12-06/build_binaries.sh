#!/usr/bin/env bash
# Builds what the device scripts run (from the repository root, build/release configured), stripped,
# into .devbuild/. Usage: build_binaries.sh NAME [PATCH]: vx of the tree as it is (with PATCH
# applied, then reverted) as .devbuild/NAME; NAME vx also copies vx_render_tests and
# vx_cli_render_tests. The binaries of this stop's calls:
#   vx_old      stop 56's vx (150a3f9: the trace code of 54ef25c), kept from its build_binaries.sh;
#   vx_list     af06ee4 (call 1's vx: the pixels listed by an atomic append);
#   vx_nocount  af06ee4 with experiment_no_count.patch (no counting in the see-through variant);
#   vx          434ff02 (call 2's: the pixels marked, the second dispatch over the image, only the
#               view rays' first walks counted in the see-through variant).
# experiment_primary_count.patch was that last change tried on d2773f0; no device came to time it.
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
