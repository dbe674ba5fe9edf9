#!/usr/bin/env bash
# README command 2: install dependencies, build, run the whole test suite:
# first every test executable against the plain libraries (label "plain"),
# then the same test objects linked against the libraries', the CLI's and the
# fixtures' AddressSanitizer + UndefinedBehaviorSanitizer twins (label
# "sanitized"; the test code itself is not instrumented), with the fuzz smoke
# tests (fuzz_smoke.*: each fuzz target on its corpus and 2000 seeded
# mutations). Both include the atomic-write kill loop. The two runs are one
# after the other: their tests share DDS domains and ports.
# The coverage-guided libFuzzer runs are scripts/fuzz.sh's.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
jobs="${GROUNDLINE_JOBS:-$(nproc)}"

echo "== build (plain and sanitizer twins) =="
scripts/build.sh full
echo "== tests (plain) =="
ctest --test-dir build --output-on-failure -j "$jobs" -L '^plain$'
echo "== tests (ASan+UBSan) =="
ctest --test-dir build --output-on-failure -j "$jobs" -L '^sanitized$'
