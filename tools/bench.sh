#!/usr/bin/env bash
# Builds the benchmarks (Release, no tests) into build-bench/ and runs the renderer benchmark.
# Arguments go to render_bench (e.g. --keep DIR). Figures and how to read them: docs/performance.md.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
cmake -S . -B build-bench -G Ninja -DCMAKE_BUILD_TYPE=Release -DHV_BUILD_TESTS=OFF -DHV_BUILD_BENCH=ON >/dev/null
cmake --build build-bench -j"$(nproc)" --target render_bench
./build-bench/render_bench "$@"
