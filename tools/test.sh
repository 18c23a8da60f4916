#!/usr/bin/env bash
# The test suite: installs what it needs, builds, runs every CPU and GL test (GL on Mesa llvmpipe,
# headless EGL; no GPU needed). Tests that use ../shared/data (HISTOVIEW_DATA) skip when absent.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh -DHV_BUILD_BENCH=OFF
export HV_LOG=${HV_LOG:-error}
cd build
ctest --output-on-failure -j"$(nproc)" --timeout 900
