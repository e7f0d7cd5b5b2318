#!/usr/bin/env bash
# The test command: installs what is missing, builds, runs every test through ctest.
#   1. the unit tests built with AddressSanitizer + UBSan (build-asan/, SINEW_SANITIZE=ON);
#   2. every libFuzzer target of tools/fuzz/ for SINEW_FUZZ_SECONDS each (default 20; build-fuzz/);
#   3. the normal build and all tests (build/): ctest's summary is the last line printed.
# SINEW_QUICK_TEST=1 skips stages 1 and 2.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh

if [[ "${SINEW_QUICK_TEST:-0}" != 1 ]]; then
  echo "== sanitizers: unit tests under ASan + UBSan (build-asan/)"
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Release -DSINEW_SANITIZE=ON >/dev/null
  cmake --build build-asan -j "$(nproc)" --target sinew_tests >/dev/null
  # Any UB report fails its test (the build recovers from UB by default).
  (cd build-asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
     ctest --output-on-failure -j "$(nproc)")
  echo "== fuzzing: ${SINEW_FUZZ_SECONDS:-20} s per target (build-fuzz/)"
  bash tools/fuzz.sh "${SINEW_FUZZ_SECONDS:-20}"
  echo "== tests (build/)"
fi

bash tools/build.sh
cd build
ctest --output-on-failure -j "$(nproc)"
