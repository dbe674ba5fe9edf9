#!/usr/bin/env bash
# Configures and builds groundline.
#   scripts/build.sh [release|asan]   (default: release)
# release -> build/,      RelWithDebInfo, tests and benchmarks
# asan    -> build-asan/, Debug with AddressSanitizer + UndefinedBehaviorSanitizer
set -euo pipefail
cd "$(dirname "$0")/.."
kind="${1:-release}"
jobs="${GROUNDLINE_JOBS:-$(nproc)}"
generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
case "$kind" in
  release)
    cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DGROUNDLINE_WERROR=ON -DGROUNDLINE_BUILD_BENCHMARKS=ON >/dev/null
    cmake --build build -j "$jobs"
    ;;
  asan)
    cmake -S . -B build-asan "${generator[@]}" -DCMAKE_BUILD_TYPE=Debug \
      -DGROUNDLINE_SANITIZE=ON -DGROUNDLINE_WERROR=ON -DGROUNDLINE_BUILD_BENCHMARKS=OFF >/dev/null
    cmake --build build-asan -j "$jobs"
    ;;
  *) echo "build.sh: unknown build kind '$kind' (expected release or asan)" >&2; exit 2 ;;
esac
