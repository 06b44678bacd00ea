#!/usr/bin/env bash
# Configures and builds vx. Usage: scripts/build.sh [release|asan|tsan|debug] [extra cmake args...]
# Build trees go to build/<kind>. Warnings are errors here (VX_WERROR=ON), as in CI.
# VX_TARGETS="a b" builds only those targets (default: all).
set -euo pipefail
cd "$(dirname "$0")/.."
kind=${1:-release}
shift || true
case "$kind" in
  release) args=(-DCMAKE_BUILD_TYPE=Release) ;;
  debug) args=(-DCMAKE_BUILD_TYPE=Debug) ;;
  asan) args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DVX_SANITIZE=address,undefined" -DVX_BUILD_BENCHMARKS=OFF) ;;
  tsan) args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DVX_SANITIZE=thread -DVX_BUILD_BENCHMARKS=OFF) ;;
  *) echo "usage: scripts/build.sh [release|asan|tsan|debug]" >&2; exit 2 ;;
esac
jobs=$(nproc)
# ccache (when installed) keys on paths relative to the repository, so clones elsewhere share hits.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}" CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"
cmake -S . -B "build/$kind" -G Ninja -DVX_WERROR=ON "${args[@]}" "$@" >/dev/null
# shellcheck disable=SC2086
ninja -C "build/$kind" -j "$jobs" ${VX_TARGETS:-}
