#!/usr/bin/env bash
# The test command: installs what is missing, builds, runs the tests through ctest.
#   1. sanitizers, only with SINEW_SANITIZER_STAGE=1 (not yet verified to pass within CI's
#      time: opt-in until it is): the unit tests built with AddressSanitizer + UBSan at -O1
#      (build-asan/, SINEW_SANITIZE=ON), without the long scene, session, render, accuracy
#      and stress tests;
#   2. fuzzing: every libFuzzer target of tools/fuzz/ for SINEW_FUZZ_SECONDS each (default 10;
#      build-fuzz/);
#   3. the normal build and all tests (build/): ctest's summary is the last line printed.
# A failure in stage 1 or 2 is announced at once, stage 3 still runs, and the script exits
# non-zero at the end. SINEW_QUICK_TEST=1 skips stages 1 and 2.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
jobs=$(nproc)
early_failures=()

if [[ "${SINEW_QUICK_TEST:-0}" != 1 && "${SINEW_SANITIZER_STAGE:-0}" == 1 ]]; then
  echo "== 1. sanitizers: unit tests under ASan + UBSan (build-asan/)"
  long_tests='scenes/|ui/|render/|accuracy/|stress|tools/test_cli|test_thread_determinism|test_sleep'
  if ! (cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE=-O1 \
          -DSINEW_SANITIZE=ON >/dev/null &&
        cmake --build build-asan -j "$jobs" --target sinew_tests >/dev/null &&
        cd build-asan &&
        # Any UB report fails its test (the build would otherwise recover from UB).
        ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
          ctest --output-on-failure -j "$jobs" -E "$long_tests"); then
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
