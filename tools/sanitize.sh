#!/usr/bin/env bash
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer (+ LeakSanitizer): configures
# build-asan/ (Debug, -DHV_SANITIZE=ON, through ccache), builds, and runs every ctest test there
# (CPU, GL on llvmpipe, CLI, fuzz corpus replay). About 17 minutes on 2 cores (docs/testing.md).
#
#   tools/sanitize.sh                          # everything
#   tools/sanitize.sh -L cpu                   # extra arguments go to ctest (-L gl, -R fuzz_, ...)
#   tools/sanitize.sh --build-only [TARGET...] # configure and build (those targets), run nothing
#
# tools/test.sh runs its sanitizer steps (CPU tests, fuzz corpora, a GL subset) on the build made
# here with --build-only. Leaks inside the Mesa/LLVM GL driver are suppressed by tools/lsan.supp
# (driver libraries only; never hv code); the environment is tools/sanitizer-env.sh's.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
source tools/ccache-env.sh

cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DHV_SANITIZE=ON -DHV_BUILD_BENCH=OFF \
  "${hv_launcher[@]}" >/dev/null
if [[ ${1:-} == --build-only ]]; then
  shift
  targets=()
  (($#)) && targets=(--target "$@")
  cmake --build build-asan -j"$(nproc)" "${targets[@]}"
  exit 0
fi
cmake --build build-asan -j"$(nproc)"

source tools/sanitizer-env.sh build-asan
cd build-asan
# Sanitized Debug code is several times slower: give each test a generous timeout.
ctest --output-on-failure -j"$(nproc)" --timeout 1800 "$@"
