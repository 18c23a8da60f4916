#!/usr/bin/env bash
# The main job on the embedded demo city: generates it (deterministic, no download), renders its
# held-out views and evaluates them against the ground truth. Output in demo-output/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh -DHV_BUILD_BENCH=OFF
./build/histoview demo --out demo-output "$@"
