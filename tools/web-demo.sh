#!/usr/bin/env bash
# The demo city in the browser, served on localhost (docs/web.md):
#   bash tools/web-demo.sh [PORT]      (default 8080), then open http://localhost:PORT/
# Builds histoview (native) and the WebAssembly version when needed, generates the demo city
# (demo-output/city), exports it to demo-output/web and serves that folder with Python's static
# server. Ctrl-C stops it.
set -euo pipefail
cd "$(dirname "$0")/.."
PORT=${1:-8080}
[[ -x build/histoview ]] || bash tools/build.sh -DHV_BUILD_BENCH=OFF
[[ -f build-web/dist/histoview_web.wasm ]] || bash tools/web-build.sh
[[ -f demo-output/city/scene.json ]] || build/histoview demo --out demo-output --generate-only
rm -rf demo-output/web
build/histoview web-export demo-output/city/scene.json demo-output/web --views demo-output/city/views.json
echo "serving demo-output/web on http://localhost:$PORT/  (a held-out view: http://localhost:$PORT/?camera=v001)"
exec python3 -m http.server "$PORT" --bind 127.0.0.1 --directory demo-output/web
