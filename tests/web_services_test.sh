#!/usr/bin/env bash
# The browser page opening a service-backed scene itself (ctest: `web_services`, labels "web" and
# "services"; docs/services.md, "In the browser").
#
#   tests/web_services_test.sh path/to/histoview [scratch-dir]
#
# A small demo city exported for the browser (histoview web-export, into the served folder), the
# local stack (tools/services.sh: MapServer's WFS and WCS behind lighttpd, on 127.0.0.1) serving
# it, then tests/web/web_services_test.mjs in headless Chromium opens the same held-out view twice
# from the page served by lighttpd: from the export's files, and with ?scene= a service
# description whose buildings come from the WFS (GeoJSON pages, extruded in the browser), the DTM
# they stand on from the WCS (an ESRI ASCII grid) and the cameras and photographs by URL; the two
# canvases must be identical or within 45 dB PSNR. Skipped (exit 77) when the browser build,
# chromium, node, lighttpd or mapserv are missing, unless CI is set (then it fails). Uses the
# browser build as it is (tests/web_test.sh and tools/web-build.sh build it).
set -uo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
source "$ROOT/tests/services/harness.sh" "$@"

for tool in node chromium lighttpd; do
  command -v "$tool" >/dev/null || missing "$tool"
done
[[ -x /usr/lib/cgi-bin/mapserv ]] || missing "mapserv (cgi-mapserver)"
[[ -f build-web/dist/histoview_web.wasm ]] || missing "the browser build (bash tools/web-build.sh)"
[[ -d tests/web/node_modules/playwright-core ]] || missing "playwright-core (cd tests/web && npm ci)"

t0=$SECONDS
"$HV" demo --out "$DIR" --generate-only --buildings 8 --photos 12 --views 3 >"$DIR/demo.out" 2>&1 ||
  { fail "demo generation: $(tail -3 "$DIR/demo.out")"; exit 1; }
# The export inside the served folder: lighttpd serves it under /files/web/ (page, wasm, files).
"$HV" web-export "$city/scene.json" "$city/web" --views "$city/views.json" >"$DIR/export.out" 2>&1 ||
  { fail "web-export: $(tail -3 "$DIR/export.out")"; exit 1; }
echo "demo and export: $((SECONDS - t0)) s"
stack_up
state=$(sed -n 's/.*(state: \(.*\))$/\1/p' "$DIR/up.out" | head -1)

read -r id w h < <(python3 -c '
import json, sys
c = json.load(open(sys.argv[1]))["cameras"][0]
print(c["id"], 200, round(200 * c["height"] / c["width"]))' "$city/views.json")
# The service description, beside the export (paths relative to it; the services by full URL).
cat >"$city/web/services.json" <<JSON
{"format": "histoview-services", "version": 1, "crs": "EPSG:2154",
 "files": "scene_web.json",
 "terrain": {"path": "WCS:$URL/mapserv?map=city&SERVICE=WCS&VERSION=2.0.1&COVERAGEID=dtm"},
 "buildings": {"path": "WFS:$URL/mapserv?map=city&TYPENAME=ms:buildings", "height": "height"},
 "cameras": {"path": "$URL/files/web/cameras.json"}}
JSON
sed "s#WFS:$URL/mapserv?map=city&TYPENAME=ms:buildings#OAPIF:$URL/mapserv/city/ogcapi/collections/buildings#" \
  "$city/web/services.json" >"$city/web/services-oapif.json"
query="camera=$id&w=$w&h=$h&k=4&points=0"
timeout -k 5 200 node tests/web/web_services_test.mjs "$URL/files/web/index.html?$query" \
  "$URL/files/web/index.html?scene=services.json&$query" "$DIR" \
  "$URL/files/web/index.html?scene=services-oapif.json&$query" >"$DIR/node.out" 2>&1
node_rc=$?
cat "$DIR/node.out"
((node_rc == 0)) && pass "the browser test (node exit code 0)" || fail "the browser test: exit code $node_rc"

# The stack saw the requests: the WFS pages as GeoJSON in the scene's CRS, the WCS as text.
log=$state/access.log
check "lighttpd's log: WFS GetFeature as GeoJSON, paged" grep -q 'REQUEST=GetFeature.*OUTPUTFORMAT=geojson.*COUNT=1000&STARTINDEX=0' "$log"
check "lighttpd's log: WCS GetCoverage as text/plain" grep -q 'REQUEST=GetCoverage&FORMAT=text%2Fplain' "$log"
echo "$((SECONDS - t0)) s"
echo "$passed passed, $failed failed"
((failed == 0))
