#!/usr/bin/env bash
# Fuzzes the input parsers (tools/fuzz/): builds the libFuzzer targets with clang, ASan and
# UBSan into build-fuzz/ (or $SINEW_FUZZ_BUILD_DIR), then runs each for SECONDS (default 60).
#
#   bash tools/fuzz.sh [SECONDS] [TARGET...]     TARGET: scene_parser obj_reader gmsh_reader tetgen_reader session_script
#
# Seeds: tools/fuzz/corpus/TARGET/ (and assets/scenes/ for the scene parser); what the fuzzer
# learns is kept in BUILD/corpus/TARGET/ for the next run. A crash, sanitizer report, leak,
# timeout (10 s) or any exception other than InputError stops that target and saves its input
# to BUILD/crashes/TARGET/; the script then exits 1. Reproduce with: BUILD/fuzz_TARGET FILE
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-60}
[[ $# -gt 0 ]] && shift
targets=("$@")
[[ ${#targets[@]} -eq 0 ]] && targets=(scene_parser obj_reader gmsh_reader tetgen_reader session_script)
build=${SINEW_FUZZ_BUILD_DIR:-build-fuzz}

# clang and its sanitizer/fuzzer runtimes (Debian 12: not pulled in by 'clang' alone).
missing=()
for p in clang libclang-rt-14-dev; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
if [[ ${#missing[@]} -gt 0 ]]; then
  echo "fuzz: installing ${missing[*]}" >&2
  [[ $(id -u) -eq 0 ]] || { echo "fuzz: must run as root to install packages" >&2; exit 1; }
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq >/dev/null
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSINEW_FUZZ=ON \
  -DCMAKE_CXX_COMPILER=clang++ >/dev/null
cmake --build "$build" -j "$(nproc)" >/dev/null

failed=()
for t in "${targets[@]}"; do
  bin="$build/fuzz_$t"
  [[ -x "$bin" ]] || { echo "fuzz: no target '$t'" >&2; exit 2; }
  corpus="$build/corpus/$t" crashes="$build/crashes/$t" log="$build/logs/$t.log"
  mkdir -p "$corpus" "$crashes" "$(dirname "$log")"
  seeds=(tools/fuzz/corpus/"$t")
  [[ $t == scene_parser ]] && seeds+=(assets/scenes)
  [[ $t == session_script ]] && seeds+=(assets/sessions)
  rc=0
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    "$bin" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -dict="tools/fuzz/$t.dict" -artifact_prefix="$crashes/" \
    "$corpus" "${seeds[@]}" >"$log" 2>&1 || rc=$?
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  if [[ $rc -eq 0 ]]; then
    echo "fuzz $t: ${seconds} s, ${runs:-?} runs, no crash"
  else
    echo "fuzz $t: FAILED (exit $rc) after ${runs:-?} runs; input saved in $crashes/, log $log:"
    grep -m1 -A25 -E '^==[0-9]+==ERROR|runtime error|deadly signal|timeout|terminate called' "$log" || tail -30 "$log"
    failed+=("$t")
  fi
done
[[ ${#failed[@]} -eq 0 ]] || { echo "fuzz: crashes in: ${failed[*]}"; exit 1; }
