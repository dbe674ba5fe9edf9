#!/usr/bin/env bash
# Configures and builds groundline in build/ (RelWithDebInfo).
#   scripts/build.sh [release|full] [TARGET...]   (default: release, all targets)
# release: the libraries, the CLI, the tests and the benchmarks.
# full:    the same and their sanitizer twins (<target>_san: every library,
#          the CLI as tools/san/groundline, every test executable, the fuzz
#          smoke drivers), instrumented with AddressSanitizer +
#          UndefinedBehaviorSanitizer; what scripts/test.sh builds.
set -euo pipefail
cd "$(dirname "$0")/.."
kind="${1:-release}"
shift || true
targets=()
for t in "$@"; do targets+=(--target "$t"); done
jobs="${GROUNDLINE_JOBS:-$(nproc)}"
generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
# ccache, when a developer has it, makes rebuilds across worktrees cheap; CI does not need it.
launcher=()
command -v ccache >/dev/null 2>&1 && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
case "$kind" in
  release) twins=OFF ;;
  full) twins=ON ;;
  *) echo "build.sh: unknown build kind '$kind' (expected release or full)" >&2; exit 2 ;;
esac
# -g1: line tables only (backtraces, profiles, sanitizer reports with
# file:line); full -g doubles the build time.
cmake -S . -B build "${generator[@]}" "${launcher[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
  -DGROUNDLINE_WERROR=ON -DGROUNDLINE_BUILD_BENCHMARKS=ON -DGROUNDLINE_SANITIZER_TWINS="$twins" >/dev/null
cmake --build build -j "$jobs" "${targets[@]}"
