#!/usr/bin/env bash
# The test command: installs what is missing, builds, runs the tests through ctest.
#   1. sanitizers: the engine's unit tests built with AddressSanitizer + UBSan (build-asan/,
#      SINEW_SANITIZE=ON: engine at -O1 with assertions, test code at -O0), without the
#      paper scenes, accuracy and stress runs and the multi-second simulations
#      (tests/CMakeLists.txt lists what is left out); any ASan or UBSan report fails;
#   2. fuzzing: every libFuzzer target of tools/fuzz/ for SINEW_FUZZ_SECONDS each (default 10;
#      build-fuzz/);
#   3. the normal build and all tests (build/): ctest's summary is the last line printed.
# A failure in stage 1 or 2 is announced at once, stage 3 still runs, and the script exits
# non-zero at the end. SINEW_QUICK_TEST=1 skips stages 1 and 2; SINEW_SANITIZER_STAGE=0
# skips stage 1 alone.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
jobs=$(nproc)
early_failures=()

if [[ "${SINEW_QUICK_TEST:-0}" != 1 && "${SINEW_SANITIZER_STAGE:-1}" == 1 ]]; then
  echo "== 1. sanitizers: engine unit tests under ASan + UBSan (build-asan/)"
  if ! (cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Release -DSINEW_SANITIZE=ON >/dev/null &&
        cmake --build build-asan -j "$jobs" --target sinew_tests >/dev/null &&
        cd build-asan &&
        # UBSan reports are not fatal by default: halt_on_error makes any one fail its test.
        ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
          ctest --output-on-failure -j "$jobs" --timeout 600); then
    early_failures+=(sanitizers)
    echo "!! stage 1 (sanitizers) FAILED: see above; the script will exit non-zero"
  fi
fi
if [[ "${SINEW_QUICK_TEST:-0}" != 1 ]]; then
  echo "== 2. fuzzing: ${SINEW_FUZZ_SECONDS:-10} s per target (build-fuzz/)"
  if ! bash tools/fuzz.sh "${SINEW_FUZZ_SECONDS:-10}"; then
    early_failures+=(fuzzing)
    echo "!! stage 2 (fuzzing) FAILED: see above; the script will exit non-zero"
  fi
  echo "== 3. tests (build/)"
fi

bash tools/build.sh
cd build
status=0
ctest --output-on-failure -j "$jobs" || status=$?
[[ ${#early_failures[@]} -eq 0 ]] || exit 1
exit "$status"
