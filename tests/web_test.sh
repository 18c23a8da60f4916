#!/usr/bin/env bash
# End-to-end test of the browser build in headless Chromium (ctest: `web`, label "web").
#
#   tests/web_test.sh path/to/histoview [scratch-dir]
#
# Builds or updates the WebAssembly version (tools/web-build.sh), installs playwright-core into
# tests/web/node_modules when missing (npm; it never downloads a browser), generates a small demo
# city, exports it (histoview web-export), renders a held-out view natively as the reference
# (with and without its lidar points), serves the export on localhost and runs
# tests/web/web_test.mjs against it: loading completes, no page errors, the canvas matches the
# native render with points and without, the point controls work, moving changes the picture.
# Exits 77 (skipped) when emcc, chromium, node or npm (or the npm package) are not available;
# in CI (CI=true, or HV_WEB_REQUIRED=1) it fails instead: there, tools/test.sh has installed and
# built all of it, so a skip would hide a broken browser build.
# For measurements: HV_WEB_SIZE=W (canvas width, default 320), HV_WEB_MEASURE=N (the median frame
# time of N frames), HV_WEB_SCREENSHOT=FILE (the whole page), HV_WEB_POSE_SCREENSHOT=FILE (the whole
# page in pose mode).
set -uo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
HV=${1:?usage: web_test.sh path/to/histoview [scratch-dir]}
HV=$(cd "$(dirname "$HV")" && pwd)/$(basename "$HV")
DIR=${2:-$(mktemp -d "${TMPDIR:-/tmp}/hv-web-test.XXXXXX")}
export HV_LOG=${HV_LOG:-error}

required=0
case ${HV_WEB_REQUIRED:-${CI:-}} in 1 | true | TRUE | True | yes) required=1 ;; esac
skip() {
  if ((required)); then
    echo "FAIL: the browser test may not skip in CI (CI=true or HV_WEB_REQUIRED=1): $1"
    exit 1
  fi
  echo "SKIPPED: $1"
  exit 77
}

for tool in emcc chromium node npm python3; do
  command -v "$tool" >/dev/null ||
    skip "$tool not found (Debian: emscripten chromium nodejs npm python3; see docs/web.md)"
done
# Outside tools/test.sh and tools/web-test.sh (HV_WEB_PREPARE=1), the browser build is only tested
# once it exists: they build it and install playwright-core.
if [[ "${HV_WEB_PREPARE:-0}" != 1 ]] &&
   [[ ! -f build-web/dist/histoview_web.wasm || ! -d tests/web/node_modules/playwright-core ]]; then
  skip "the browser build or playwright-core is not prepared (run: bash tools/test.sh or bash tools/web-test.sh)"
fi
if [[ ! -d tests/web/node_modules/playwright-core ]]; then
  (cd tests/web && npm ci --no-audit --no-fund --loglevel=error) ||
    skip "npm could not install playwright-core into tests/web/node_modules"
fi
# Built, or brought up to date (an incremental build: seconds when nothing changed; a stale build
# would test yesterday's page against today's native render).
bash tools/web-build.sh >"${TMPDIR:-/tmp}/hv-web-build.log" 2>&1 ||
  { echo "FAIL: tools/web-build.sh"; tail -30 "${TMPDIR:-/tmp}/hv-web-build.log"; exit 1; }

rm -rf "$DIR"
mkdir -p "$DIR"
"$HV" demo --out "$DIR" --generate-only --buildings 8 --photos 12 --views 3 >"$DIR/demo.out" 2>&1 ||
  { echo "FAIL: demo generation"; cat "$DIR/demo.out"; exit 1; }
city=$DIR/city
"$HV" web-export "$city/scene.json" "$DIR/web" --views "$city/views.json" >"$DIR/export.out" 2>&1 ||
  { echo "FAIL: web-export"; cat "$DIR/export.out"; exit 1; }
cat "$DIR/export.out"
[[ -f $DIR/web/histoview_web.wasm && -f $DIR/web/index.html ]] ||
  { echo "FAIL: the export has no page or no WebAssembly"; exit 1; }
# One photograph without a date (the last), for the page's list of undated photographs. An undated
# photograph passes the open time window, so the references below (no window) are unchanged.
python3 -c '
import json, sys
doc = json.load(open(sys.argv[1]))
doc["cameras"][-1].pop("date", None)
json.dump(doc, open(sys.argv[1], "w"), indent=1)' "$DIR/web/cameras.json" ||
  { echo "FAIL: could not remove a date from the export"; exit 1; }

# The held-out view at the test size (its aspect ratio), and the native reference render.
read -r id w h < <(python3 -c '
import json, sys
c = json.load(open(sys.argv[1]))["cameras"][0]
w = int(sys.argv[2].split("x")[0]) if sys.argv[2] else 320
print(c["id"], w, round(w * c["height"] / c["width"]))' "$city/views.json" "${HV_WEB_SIZE:-}")
"$HV" render "$city/scene.json" --views "$city/views.json" --size "${w}x${h}" --k 8 --out "$DIR/render" \
  >"$DIR/render.out" 2>&1 || { echo "FAIL: histoview render"; cat "$DIR/render.out"; exit 1; }
cp "$DIR/render/$id.png" "$DIR/web/reference.png"
# The same view with the demo's lidar scan as textured sprites (the page draws them by default).
"$HV" render "$city/scene.json" --views "$city/views.json" --size "${w}x${h}" --k 8 --points --out "$DIR/render-points" \
  >"$DIR/render-points.out" 2>&1 || { echo "FAIL: histoview render --points"; cat "$DIR/render-points.out"; exit 1; }
cp "$DIR/render-points/$id.png" "$DIR/web/reference-points.png"

# A static server on a free port.
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
python3 -m http.server "$port" --bind 127.0.0.1 --directory "$DIR/web" >"$DIR/server.log" 2>&1 &
server=$!
trap 'kill $server 2>/dev/null' EXIT
for _ in $(seq 50); do
  python3 -c "import urllib.request; urllib.request.urlopen('http://127.0.0.1:$port/index.html')" 2>/dev/null && break
  sleep 0.2
done

measure=()
[[ -n ${HV_WEB_MEASURE:-} ]] && measure=(--measure "$HV_WEB_MEASURE")
node tests/web/web_test.mjs "http://127.0.0.1:$port/?camera=$id&w=$w&h=$h&k=8" "$DIR" "${measure[@]}"
