#!/usr/bin/env bash
# Every test: set up, then a Release build with warnings as errors and the whole CTest suite,
# then the sanitizer builds (ASan+UBSan over everything that runs without a GPU driver, TSan
# over the engine's threaded code). Pass --quick to run only the Release suite.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
export VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.json # Tests render on lavapipe.
jobs=$(nproc)

bash scripts/build.sh release
ctest --test-dir build/release --output-on-failure -j "$jobs"
[[ "${1:-}" == "--quick" ]] && exit 0

bash scripts/build.sh asan
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build/asan --output-on-failure -j "$jobs" -LE "vulkan|slow"

if [[ -d engine ]]; then
  # Every thread of ours under TSan: the job system and streaming, the facade (a game's throwing
  # generator, clock and log handler), shared PostgreSQL worlds (listener, I/O lane) and the log.
  # Without precompiled headers (VX_PCH): this build also finds a file that forgets an #include
  # the shared header would otherwise supply.
  VX_TARGETS="vx_engine_tests vx_facade_tests vx_shared_world_tests vx_world_tests" bash scripts/build.sh tsan -DVX_PCH=OFF
  TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1" \
    ctest --test-dir build/tsan --output-on-failure -j "$jobs" -L engine
  TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1" \
    ctest --test-dir build/tsan --output-on-failure -j "$jobs" -L world -R '^(Log|Median|RecordBatchEncoder|PgStore|PgListener|Backends/StoreSuite)\.'
fi
