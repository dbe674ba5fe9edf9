#!/usr/bin/env bash
# README command 2: install dependencies, build, run the whole test suite,
# first in the release build, then again with the libraries, tools and fuzz
# drivers under ASan+UBSan (the test code itself uninstrumented). Both include the
# atomic-write kill loop; the ASan+UBSan run adds the fuzz smoke tests
# (fuzz_smoke.*: each fuzz target on its corpus and 2000 seeded mutations);
# the coverage-guided libFuzzer runs are scripts/fuzz.sh's.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
jobs="${GROUNDLINE_JOBS:-$(nproc)}"

echo "== release build =="
scripts/build.sh release
echo "== tests (release) =="
ctest --test-dir build --output-on-failure -j "$jobs"

echo "== ASan+UBSan build =="
scripts/build.sh asan
echo "== tests (ASan+UBSan) =="
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure -j "$jobs"
