#!/usr/bin/env bash
# Configures and builds histoview (Release with debug info) into build/, through ccache when it is
# installed (tools/ccache-env.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
source tools/ccache-env.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "${hv_launcher[@]}" "$@" >/dev/null
cmake --build build -j"$(nproc)"
