#!/usr/bin/env bash
# Builds the benchmarks (Release, no tests) into build-bench/ and runs them: the renderer benchmark
# (render_bench) then the many-images benchmark (many_images_bench).
# Usage: tools/bench.sh [render|many] [--keep DIR]
#   render / many: run only that benchmark (default: both, one after the other);
#   --keep DIR: generate the scenes into DIR and leave them there (passed to each benchmark).
# Figures and how to read them: docs/performance.md.
set -euo pipefail
cd "$(dirname "$0")/.."
which=both
case "${1:-}" in
  render | many) which=$1; shift ;;
esac
bash tools/install-deps.sh
cmake -S . -B build-bench -G Ninja -DCMAKE_BUILD_TYPE=Release -DHV_BUILD_TESTS=OFF -DHV_BUILD_BENCH=ON >/dev/null
targets=()
[[ $which == many ]] || targets+=(render_bench)
[[ $which == render ]] || targets+=(many_images_bench)
cmake --build build-bench -j"$(nproc)" --target "${targets[@]}"
status=0
if [[ $which != many ]]; then
  ./build-bench/render_bench "$@" || status=$?
fi
if [[ $which != render ]]; then
  [[ $which == both ]] && echo
  ./build-bench/many_images_bench "$@" || status=$?
fi
exit "$status"
