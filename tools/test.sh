#!/usr/bin/env bash
# The test suite: installs what it needs, builds, runs every CPU and GL test (GL on Mesa llvmpipe,
# headless EGL; no GPU needed). Tests that use ../shared/data (HISTOVIEW_DATA) skip when absent.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh -DHV_BUILD_BENCH=OFF
export HV_LOG=${HV_LOG:-error}
# A real COLMAP model of the Sceaux photographs for the COLMAP reader's tests, when colmap and the
# real data are on this machine (made once into build/; exit 77 = skipped, the tests skip too).
status=0
bash tools/colmap-sceaux.sh build/colmap-sceaux || status=$?
[[ $status == 0 || $status == 77 ]]
cd build
ctest --output-on-failure -j"$(nproc)" --timeout 900
