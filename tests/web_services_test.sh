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
# Points from 3D Tiles (web/services_layers.js): the demo's lidar as a tileset served as static
# files, a copy with one tile missing (the server answers 404), one with a malformed tileset.json.
"$HV" points-tiles "$city/points.las" "$city/tiles" --points-per-tile 4000 >"$DIR/tiles.out" 2>&1 ||
  { fail "points-tiles: $(tail -3 "$DIR/tiles.out")"; exit 1; }
cp -r "$city/tiles" "$city/tiles-404"
gone=$(cd "$city/tiles-404" && ls r?*.pnts | head -1)
rm -f "$city/tiles-404/$gone"
mkdir -p "$city/tiles-bad"
echo '{"asset": {"version": "1.0"}, "geometricError": 10, "root": {"boundingVolume": {"box": [0, 0]}, "geometricError": 1}}' \
  >"$city/tiles-bad/tileset.json"
echo "demo and export: $((SECONDS - t0)) s"
# Cameras and photographs from services (tests/web/web_services_cameras_test.mjs): the export's
# cameras as a point layer that tools/services.sh serves by WFS (ms:cameras; the image paths
# relative to the city folder, i.e. web/images/…), and the photographs as tiled pyramidal TIFFs
# that iipsrv serves (IIIF), when it is installed.
printf '{"crs": "EPSG:2154", "cameras": {"path": "web/cameras.json"}}\n' >"$city/cameras-web.json"
"$HV" cameras export "$city/cameras-web.json" --ogr "$city/cameras.gpkg" >"$DIR/cameras-export.out" 2>&1 ||
  fail "cameras export --ogr: $(tail -3 "$DIR/cameras-export.out")"
iiif=0
if [[ -x ${HV_IIPSRV:-/usr/lib/iipimage-server/iipsrv.fcgi} ]]; then
  iiif=1
  mkdir -p "$city/iiif"
  for png in "$city"/images/*.png; do
    python3 tests/services/pyramid_tiff.py "$png" "$city/iiif/$(basename "$png" .png).tif" &
    while (($(jobs -rp | wc -l) >= 2)); do sleep 0.1; done
  done
  wait
fi
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

# The service layers (tests/web/web_services_layers_test.mjs): points from the tileset (every
# tile), compared with the export's points, with the point pass on; then the two faults.
layer() {  # layer NAME KEY ENTRY: services.json with one more source
  python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); d[sys.argv[3]] = json.loads(sys.argv[4])
json.dump(d, open(sys.argv[2], "w"))' "$city/web/services.json" "$city/web/services-$1.json" "$2" "$3"
}
layer points points "{\"path\": \"$URL/files/tiles/tileset.json\", \"tolerance\": 0}"
layer points-404 points "{\"path\": \"$URL/files/tiles-404/tileset.json\", \"tolerance\": 0}"
layer points-bad points "{\"path\": \"$URL/files/tiles-bad/tileset.json\", \"tolerance\": 0}"
pquery="camera=$id&w=$w&h=$h&k=4&points=true&point-color=rgb"
page=$URL/files/web/index.html
# The orthophoto from MapCache's WMTS: an export whose scene.json reads it natively (GDAL's WMTS
# driver, the same tiles) against the page reading it itself, over the overview (much terrain
# that no photograph reaches), and the page with the orthophoto switched off (it must show).
wmts="WMTS:$URL/mapcache/wmts?SERVICE=WMTS&REQUEST=GetCapabilities"
python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); d["orthophoto"] = {"path": sys.argv[3]}
json.dump(d, open(sys.argv[2], "w"))' "$city/scene.json" "$city/scene-wmts.json" "$wmts"
"$HV" web-export "$city/scene-wmts.json" "$city/web-wmts" --views "$city/views.json" >"$DIR/export-wmts.out" 2>&1 ||
  fail "web-export of the WMTS scene: $(tail -3 "$DIR/export-wmts.out")"
sed "s#/files/web/cameras.json#/files/web-wmts/cameras.json#" "$city/web/services.json" >"$city/web-wmts/services.json"
python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); d["orthophoto"] = {"path": sys.argv[2]}
json.dump(d, open(sys.argv[1], "w"))' "$city/web-wmts/services.json" "$wmts"
oquery="w=200&h=150&k=4&points=0"
opage=$URL/files/web-wmts/index.html
timeout -k 5 500 node tests/web/web_services_layers_test.mjs "$DIR" "$page?$pquery" "$page?scene=services-points.json&$pquery" \
  "$page?scene=services-points-404.json&$pquery" "$page?scene=services-points-bad.json&$pquery" \
  "$opage?$oquery" "$opage?scene=services.json&$oquery" "$opage?scene=services.json&$oquery&orthophoto=false" \
  >"$DIR/node-layers.out" 2>&1
node_rc=$?
cat "$DIR/node-layers.out"
((node_rc == 0)) && pass "the browser test of the layers (node exit code 0)" || fail "the browser test of the layers: exit code $node_rc"

# --- a description without "files" (tests/web/web_services_nofiles_test.mjs): no web export at
# all; the terrain meshed from the WCS grid in the module, the cameras, photographs and held-out
# views by URL from outside the export's folder, the CRS as a PROJ string (`histoview info` prints
# it) for the page's EPSG:4978 fit of the tileset's points. The photographs are the export's JPEGs
# copied into the city's folder (the demo's own PNGs differ from them by the JPEG re-encoding: the
# picture would then differ by that, not by the scene).
proj=$("$HV" info "$city/scene.json" 2>/dev/null | sed -n 's/^  proj4 *//p' | head -1)
[[ -n $proj ]] || fail "histoview info prints the scene CRS as a PROJ string"
python3 - "$city" "$URL" "$proj" <<'PY'
import json, sys
import os, shutil
city, url, proj = sys.argv[1:4]
cams = json.load(open(city + "/web/cameras.json"))
for c in cams["cameras"]:
    for key in ("image", "mask"):
        if key in c:
            os.makedirs(os.path.dirname(f"{city}/photographs/{c[key]}"), exist_ok=True)
            shutil.copy(f"{city}/web/{c[key]}", f"{city}/photographs/{c[key]}")
            c[key] = "photographs/" + c[key]
json.dump(cams, open(city + "/cameras-photographs.json", "w"))
d = {"format": "histoview-services", "version": 1, "crs": "EPSG:2154", "projection": proj, "views": "views.json",
     "terrain": {"path": f"WCS:{url}/mapserv?map=city&SERVICE=WCS&VERSION=2.0.1&COVERAGEID=dtm"},
     "buildings": {"path": f"WFS:{url}/mapserv?map=city&TYPENAME=ms:buildings", "height": "height"},
     "cameras": {"path": "cameras-photographs.json"}}
json.dump(d, open(city + "/services-nofiles.json", "w"))
json.dump(dict(d, points={"path": f"{url}/files/tiles/tileset.json", "tolerance": 0}),
          open(city + "/services-nofiles-points.json", "w"))
json.dump(dict(d, terrain={"path": f"WCS:{url}/files/no-such-wcs?map=city&COVERAGEID=dtm"},
               cameras={"path": f"{url}/files/no-such-cameras.json"}), open(city + "/services-missing.json", "w"))
PY
# The traffic off: the description names no traffic (the page does not read one from services).
nquery="$query&traffic=false"
npquery="$pquery&traffic=false"
timeout -k 5 400 node tests/web/web_services_nofiles_test.mjs "$DIR" "$page?$nquery" "$page?scene=../services-nofiles.json&$nquery" \
  "$page?scene=services-points.json&$npquery" "$page?scene=../services-nofiles-points.json&$npquery" "$page?scene=../services-missing.json&$nquery" \
  >"$DIR/node-nofiles.out" 2>&1
node_rc=$?
cat "$DIR/node-nofiles.out"
((node_rc == 0)) && pass "the browser test without an export (node exit code 0)" ||
  fail "the browser test without an export: exit code $node_rc"
kill -HUP "$(cat "$state/lighttpd.pid")" 2>/dev/null; sleep 1  # lighttpd writes its buffered log out
# Every request the page without an export made (its Referer), in lighttpd's log: the services,
# the demo's own files and the page's files, none of the export's.
check "lighttpd's log: the page without an export fetched no export file" python3 - "$state/access.log" <<'PY'
import re, sys
lines = [l for l in open(sys.argv[1]) if "scene=../services-nofiles" in l]
asked = [re.search(r'"GET ([^ ]+)', l).group(1) for l in lines if '"GET ' in l]
export = [a for a in asked if a.startswith("/files/web/") and
          not re.match(r"/files/web/(index\.html|[a-z0-9_]+\.js|histoview\.css|histoview_web\.wasm)(\?|$)", a)]
print("      ", len(asked), "requests;", "export files:", export[:5])
ok = asked and not export and any("GetCoverage" in a for a in asked) and any("/files/photographs/" in a for a in asked)
sys.exit(0 if ok else 1)
PY

# The stack saw the requests: the WFS pages as GeoJSON in the scene's CRS, the WCS as text.
log=$state/access.log
check "lighttpd's log: the tileset and its pnts tiles" grep -q 'GET /files/tiles/r[^ ]*\.pnts' "$log"
check "lighttpd's log: the tileset.json" grep -q 'GET /files/tiles/tileset\.json' "$log"
check "lighttpd's log: WMTS capabilities and tiles" grep -q 'GET /mapcache/wmts/1\.0\.0/orthophoto/' "$log"
check "lighttpd's log: WFS GetFeature as GeoJSON, paged" grep -q 'REQUEST=GetFeature.*OUTPUTFORMAT=geojson.*COUNT=1000&STARTINDEX=0' "$log"
check "lighttpd's log: WCS GetCoverage as text/plain" grep -q 'REQUEST=GetCoverage&FORMAT=text%2Fplain' "$log"

# --- cameras from the WFS layer, photographs from IIIF (tests/web/web_services_cameras_test.mjs)
# With iipsrv: the fault proxy (tests/services/fault_proxy.py) in front of the stack, for
# photographs whose previews arrive and whose full images answer 404 (the fault 404-wide).
purl=
if ((iiif)); then
  pport=$(free_port)
  python3 tests/services/fault_proxy.py "$pport" "$URL" "$DIR/proxy.log" >"$DIR/proxy.out" 2>&1 &
  proxy_pid=$!
  for _ in $(seq 50); do grep -q "fault proxy on" "$DIR/proxy.out" 2>/dev/null && break; sleep 0.1; done
  check "fault proxy started" grep -q "fault proxy on" "$DIR/proxy.out"
  purl=http://127.0.0.1:$pport
fi
python3 - "$city" "$URL" "$iiif" "$purl" <<'PY'
import json, sqlite3, struct, sys
city, url, iiif, purl = sys.argv[1], sys.argv[2], sys.argv[3] == "1", sys.argv[4]
web = city + "/web"
base = {"format": "histoview-services", "version": 1, "crs": "EPSG:2154",
        "terrain": {"path": f"WCS:{url}/mapserv?map=city&SERVICE=WCS&VERSION=2.0.1&COVERAGEID=dtm"},
        "buildings": {"path": f"WFS:{url}/mapserv?map=city&TYPENAME=ms:buildings", "height": "height"}}
def describe(path, files, cameras):
    json.dump(dict(base, files=files, cameras={"path": cameras}), open(path, "w"))
wfs = f"WFS:{url}/mapserv?map=city&TYPENAME=ms:cameras"
# Beside the city's files: the layer's image paths (web/images/…) are relative to it.
describe(city + "/services-wfs-cameras.json", "web/scene_web.json", wfs)
# A malformed camera layer: a static file answers the GetFeature (lighttpd ignores the query).
open(city + "/malformed-cameras.json", "w").write('{"type": "FeatureCollection", "features": [{"type": "Feat')
describe(city + "/services-malformed.json", "web/scene_web.json",
         f"WFS:{url}/files/malformed-cameras.json?map=city&TYPENAME=ms:cameras")
cams = json.load(open(web + "/cameras.json"))
ids = [c["id"] for c in cams["cameras"]]
if iiif:
    # The same cameras by file with every photograph from iipsrv, and the layer likewise (its
    # image column rewritten: MapServer reads the GeoPackage at each request).
    for c in cams["cameras"]:
        c["image"] = f"{url}/iiif?IIIF={c['id']}.tif/info.json"
    json.dump(cams, open(web + "/cameras-iiif.json", "w"))
    describe(web + "/services-iiif-file.json", "scene_web.json", "cameras-iiif.json")
    # Every photograph through the proxy: the previews pass, the full images answer 404.
    for c in cams["cameras"]:
        c["image"] = f"{purl}/404-wide/iiif?IIIF={c['id']}.tif/info.json"
    json.dump(cams, open(web + "/cameras-iiif-full-404.json", "w"))
    describe(web + "/services-iiif-full-404.json", "scene_web.json", "cameras-iiif-full-404.json")
    db = sqlite3.connect(city + "/cameras.gpkg")
    # The GeoPackage's R-tree triggers call SQL functions of GDAL / SpatiaLite: the few they use,
    # for points (the geometry is not changed; they fire on any update).
    def point(blob):
        envelope = {0: 0, 1: 32, 2: 48, 3: 48, 4: 64}[(blob[3] >> 1) & 7]
        wkb = blob[8 + envelope:]
        return struct.unpack(("<" if wkb[0] == 1 else ">") + "dd", wkb[5:21])
    db.create_function("ST_IsEmpty", 1, lambda g: 0 if g else 1)
    for name, i in (("ST_MinX", 0), ("ST_MaxX", 0), ("ST_MinY", 1), ("ST_MaxY", 1)):
        db.create_function(name, 1, lambda g, i=i: point(g)[i])
    db.execute("UPDATE cameras SET image = ? || id || '.tif/info.json'", (f"{url}/iiif?IIIF=",))
    db.commit()
    db.close()
# One photograph missing (HTTP 404), the others as exported.
cams = json.load(open(web + "/cameras.json"))
cams["cameras"][0]["image"] = f"{url}/files/web/images/missing.jpg"
json.dump(cams, open(web + "/cameras-404.json", "w"))
describe(web + "/services-404.json", "scene_web.json", "cameras-404.json")
print(ids[0], len(ids))
PY
read -r first_id photo_count < <(python3 -c 'import json,sys; c=json.load(open(sys.argv[1]))["cameras"]; print(c[0]["id"], len(c))' "$city/web/cameras.json")
page=$URL/files/web/index.html
args=(--files "$page?$query" --wfs "$page?scene=../services-wfs-cameras.json&$query"
      --malformed "$page?scene=../services-malformed.json&$query" --missing "$page?scene=services-404.json&$query"
      --photos "$photo_count" --out "$DIR")
((iiif)) && args+=(--iiif-file "$page?scene=services-iiif-file.json&$query"
                   --iiif-full-404 "$page?scene=services-iiif-full-404.json&$query")
timeout -k 5 400 node tests/web/web_services_cameras_test.mjs "${args[@]}" >"$DIR/node-cameras.out" 2>&1
node_rc=$?
cat "$DIR/node-cameras.out"
((node_rc == 0)) && pass "the browser test of cameras and photographs from services (node exit code 0)" ||
  fail "the browser test of cameras and photographs from services: exit code $node_rc"
kill -HUP "$(cat "$state/lighttpd.pid")" 2>/dev/null; sleep 1  # lighttpd writes its buffered log out
check "lighttpd's log: WFS GetFeature of ms:cameras as GeoJSON" \
  grep -q 'REQUEST=GetFeature&TYPENAMES=ms%3Acameras&OUTPUTFORMAT=geojson' "$log"
if ((iiif)); then
  # For one photograph: its description, then its preview, then its full image (lines in order).
  check "lighttpd's log: IIIF info.json, then the preview, then the full image ($first_id)" python3 - "$log" "$first_id" <<'PY'
import re, sys
lines = [l for l in open(sys.argv[1]) if f"IIIF={sys.argv[2]}.tif/" in l]
kinds = []
for l in lines:
    if "/info.json" in l: kinds.append("info")
    else:
        m = re.search(r"/full/(\d+),/0/default\.jpg", l)
        if m: kinds.append(int(m.group(1)))
print("      ", kinds)
# The page's first IIIF load: info, a width, a larger width (later loads repeat the pattern).
ok = len(kinds) >= 3 and kinds[0] == "info" and all(isinstance(k, int) for k in kinds[1:3]) and kinds[1] < kinds[2]
sys.exit(0 if ok else 1)
PY
fi
echo "$((SECONDS - t0)) s"
echo "$passed passed, $failed failed"
((failed == 0))
