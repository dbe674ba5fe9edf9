#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/) and runs them.
#   scripts/fuzz.sh [TARGET[,TARGET...]|all] [RUNS]   (default: all, 100000 executions each)
# build-fuzz/: clang-14, the libraries with -fsanitize=fuzzer-no-link,address,undefined,
# the fuzz executables with -fsanitize=fuzzer,address,undefined (GROUNDLINE_BUILD_FUZZERS).
# Each target starts from its committed corpus fuzz/corpus/<target>/ and keeps
# what it finds in build-fuzz/corpus/<target>/ (not committed); a finding is
# written to build-fuzz/findings/<target>/. Prints one line per target:
# executions, coverage (libFuzzer's cov:), findings. Exits 1 if any target failed.
# GROUNDLINE_FUZZ_MAX_TIME=S stops each target after S seconds even if RUNS is not reached;
# GROUNDLINE_FUZZ_PARALLEL=N runs N targets at once.
# GROUNDLINE_FUZZ_MAX_LEN=B caps an input at B bytes (default 65536; the
# readers are line- or key-based, so a few kB already reach every branch, and
# smaller inputs run faster).
set -euo pipefail
cd "$(dirname "$0")/.."
which="${1:-all}"
runs="${2:-100000}"
jobs="${GROUNDLINE_JOBS:-$(nproc)}"
command -v clang++-14 >/dev/null || { echo "fuzz.sh: clang++-14 not found (scripts/setup.sh installs it)" >&2; exit 2; }
launcher=()
command -v ccache >/dev/null 2>&1 && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
# -O1: what libFuzzer's documentation uses; -g1 for file:line in reports.
CC=clang-14 CXX=clang++-14 cmake -S . -B build-fuzz -G Ninja "${launcher[@]}" -DCMAKE_BUILD_TYPE=Debug \
  -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" -DCMAKE_C_FLAGS_DEBUG="-O1 -g1" \
  -DGROUNDLINE_BUILD_FUZZERS=ON -DGROUNDLINE_BUILD_TESTS=OFF -DGROUNDLINE_BUILD_BENCHMARKS=OFF \
  -DGROUNDLINE_WERROR=ON >/dev/null
if [ "$which" = all ]; then mapfile -t targets < build-fuzz/fuzz/targets.txt; else IFS=, read -ra targets <<<"$which"; fi
build_targets=()
for t in "${targets[@]}"; do build_targets+=(--target "fuzz_$t"); done
cmake --build build-fuzz -j "$jobs" "${build_targets[@]}"

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:symbolize=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
mkdir -p build-fuzz/logs
# One target: its log, then a status file with libFuzzer's exit code.
run_one() {
  local t=$1 corpus=build-fuzz/corpus/$1 findings=build-fuzz/findings/$1
  local log=build-fuzz/logs/$1.log status=0
  mkdir -p "$corpus" "$findings"
  local extra=()
  [ -n "${GROUNDLINE_FUZZ_MAX_TIME:-}" ] && extra+=(-max_total_time="$GROUNDLINE_FUZZ_MAX_TIME")
  # -timeout: an input that takes over 10 s is a hang; -rss_limit_mb: a leak or a blow-up.
  build-fuzz/fuzz/fuzz_"$t" "$corpus" "fuzz/corpus/$t" -runs="$runs" -timeout=10 \
    -rss_limit_mb=2048 -max_len="${GROUNDLINE_FUZZ_MAX_LEN:-65536}" -print_final_stats=1 -artifact_prefix="$findings/" \
    "${extra[@]}" >"$log" 2>&1 || status=$?
  echo "$status" >"build-fuzz/logs/$t.status"
}
# GROUNDLINE_FUZZ_PARALLEL=N runs N targets at a time (default 1).
parallel="${GROUNDLINE_FUZZ_PARALLEL:-1}"
for t in "${targets[@]}"; do
  rm -f "build-fuzz/logs/$t.status"
  while [ "$(jobs -rp | wc -l)" -ge "$parallel" ]; do wait -n || true; done
  run_one "$t" &
done
wait

failed=0
printf '%-26s %12s %8s %8s %7s  %s\n' target executions cov ft exec/s findings
for t in "${targets[@]}"; do
  log=build-fuzz/logs/$t.log findings=build-fuzz/findings/$t
  status=$(cat "build-fuzz/logs/$t.status" 2>/dev/null || echo "?")
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1 || true)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | cut -d' ' -f2 || true)
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | cut -d' ' -f2 || true)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1 || true)
  found=$(find "$findings" -type f | wc -l)
  what="none"
  if [ "$status" != 0 ]; then
    failed=1
    what="FAILED (exit $status, $found file(s) in $findings; log $log)"
  elif [ "$found" -ne 0 ]; then
    what="$found earlier file(s) in $findings"
  fi
  printf '%-26s %12s %8s %8s %7s  %s\n' "$t" "${execs:-?}" "${cov:-?}" "${ft:-?}" "${rate:-?}" "$what"
done
exit "$failed"
