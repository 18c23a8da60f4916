#!/usr/bin/env bash
# The browser build's end-to-end test in headless Chromium (docs/web.md), on its own: installs
# Emscripten and Chromium (apt) and playwright-core (npm) when missing, builds the WebAssembly
# version and the native one, and runs tests/web_test.sh. tools/test.sh does the same among its
# steps (web-build, web-npm, web).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
# By command, not by package: a machine may have Node.js and npm from elsewhere (NodeSource's
# nodejs bundles npm and conflicts with Debian's npm package).
for need in emcc:emscripten chromium:chromium node:nodejs npm:npm; do
  command -v "${need%%:*}" >/dev/null 2>&1 ||
    { apt-get update -qq && apt-get install -y -qq --no-install-recommends "${need#*:}"; }
done
bash tools/build.sh -DHV_BUILD_BENCH=OFF
bash tools/web-build.sh
HV_WEB_PREPARE=1 bash tests/web_test.sh build/histoview
