#!/usr/bin/env bash
# Configures and builds vx. Usage: scripts/build.sh [release|asan|tsan|debug] [extra cmake args...]
# Build trees go to build/<kind>. Warnings are errors here (VX_WERROR=ON), as in CI.
# VX_TARGETS="a b" builds only those targets (default: all).
set -euo pipefail
cd "$(dirname "$0")/.."
kind=${1:-release}
shift || true
sanitizer_flags=("-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG"
                 -DVX_GPU_TESTS=OFF)
case "$kind" in
  release) args=(-DCMAKE_BUILD_TYPE=Release) ;;
  debug) args=(-DCMAKE_BUILD_TYPE=Debug) ;;
  # Sanitizer builds: -O1, the sanitizers' recommended level, and -g1, line tables without
  # local variables: reports keep their file:line stacks, and the heaviest file (OpenVDB
  # templates) compiles in half the time of -O2 -g (49 s against 94 s under ASan here). They
  # leave out the tests that render (VX_GPU_TESTS): scripts/test.sh runs those only in Release.
  asan) args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DVX_SANITIZE=address,undefined" -DVX_BUILD_BENCHMARKS=OFF
              "${sanitizer_flags[@]}") ;;
  tsan) args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DVX_SANITIZE=thread -DVX_BUILD_BENCHMARKS=OFF
              "${sanitizer_flags[@]}") ;;
  *) echo "usage: scripts/build.sh [release|asan|tsan|debug]" >&2; exit 2 ;;
esac
jobs=$(nproc)
# ccache (when installed) keys on paths relative to the repository, so clones elsewhere share hits.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}" CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"
cmake -S . -B "build/$kind" -G Ninja -DVX_WERROR=ON "${args[@]}" "$@" >/dev/null
# shellcheck disable=SC2086
ninja -C "build/$kind" -j "$jobs" ${VX_TARGETS:-}
