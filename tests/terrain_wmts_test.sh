#!/usr/bin/env bash
# Elevation by WMTS: the demo city's DTM served as float32 tiles by MapCache over MapServer's WMS
# (ctest: `terrain_wmts`, label "services"; docs/services.md, "Elevation by WMTS"):
#
#   tests/terrain_wmts_test.sh path/to/histoview path/to/hv_tests [scratch-dir]
#
# Generates a small demo city, serves it with tools/services.sh (lighttpd on 127.0.0.1, MapCache's
# WMTS under /elevation whose tiles are MapServer's float32 GeoTIFFs, passed through byte for
# byte), and checks that
#   - the terrain read from the WMTS (a GDAL_WMTS description: the capabilities' URL, one band of
#     Float32) has the file's grid and heights (hv_tests TerrainWmts.SameHeightsAsTheFile: every
#     cell within 1 mm);
#   - the held-out views render the same from the WMTS terrain as from the file (identical or
#     >= 45 dB), the tiles asked by GetTile and MapCache asking MapServer's WMS for GeoTIFFs;
#   - a second load sends no tile request (GDAL's tile cache in histoview's cache folder).
# The stack is stopped on exit, failure included. Exit 77 (skipped) when lighttpd, MapServer or
# MapCache is missing, unless CI is set: then it fails. Prints "N passed, M failed".
set -uo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
TESTS=${2:?usage: terrain_wmts_test.sh path/to/histoview path/to/hv_tests [scratch-dir]}
TESTS=$(cd "$(dirname "$TESTS")" && pwd)/$(basename "$TESTS")
set -- "$1" "${@:3}"
source "$ROOT/tests/services/harness.sh" "$@"  # HV, DIR; checks, runs, clean-up

for tool in lighttpd python3 timeout; do command -v "$tool" >/dev/null || missing "$tool not found"; done
[[ -x ${HV_MAPSERV:-/usr/lib/cgi-bin/mapserv} ]] || missing "mapserv not found (cgi-mapserver)"
[[ -x ${HV_MAPCACHE:-/usr/lib/cgi-bin/mapcache} ]] || missing "mapcache not found (mapcache-cgi)"

run demo demo --out "$DIR" --generate-only --buildings 8 --photos 12 --views 3
expect_clean demo 0
stack_up
state=$(sed -n 's/^serving .* (state: \(.*\))$/\1/p' "$DIR/up.out")
# GDAL's WMTS driver reads 8-bit RGBA tiles unless told: a GDAL_WMTS description says one band of
# Float32, and that its tiles go to GDAL's tile cache (docs/services.md).
cat >"$city/dtm-wmts.xml" <<XML
<GDAL_WMTS>
  <GetCapabilitiesUrl>$URL/elevation/wmts?SERVICE=WMTS&amp;REQUEST=GetCapabilities</GetCapabilitiesUrl>
  <Layer>dtm</Layer>
  <BandsCount>1</BandsCount>
  <DataType>Float32</DataType>
  <Cache />
</GDAL_WMTS>
XML
for s in file:dtm.tif wmts:dtm-wmts.xml; do
  printf '{"crs": "EPSG:2154", "terrain": {"path": "%s"}, "buildings": {"path": "buildings.geojson", "height": "height"}, "cameras": {"path": "cameras.json"}}\n' \
    "${s#*:}" >"$city/${s%%:*}.json"
done

requests() {
  kill -HUP "$(cat "$state/lighttpd.pid")" 2>/dev/null
  sleep 0.5
  grep -cE "$1" "$state/access.log"
}

# The heights, cell by cell.
HV_TEST_WMTS_TERRAIN=$city/dtm-wmts.xml HV_TEST_WMTS_TERRAIN_FILE=$city/dtm.tif \
  timeout -k 5 "$RUN_LIMIT" "$TESTS" --gtest_filter='TerrainWmts.*' >"$DIR/heights.out" 2>&1
rc=$?
grep -E "terrain from WMTS|Failure|Expected|Which is|skipped|SKIPPED" "$DIR/heights.out" | sed 's/^/      /' | head -20
check "the WMTS terrain has the file's grid and heights (TerrainWmts.SameHeightsAsTheFile)" \
  bash -c "test $rc -eq 0 && grep -q 'terrain from WMTS' '$DIR/heights.out' && ! grep -q SKIPPED '$DIR/heights.out'"
check "tiles asked by GetTile under /elevation/" test "$(requests 'GET /elevation/wmts/1.0.0/dtm/')" -ge 1
check "MapCache asked MapServer's WMS for GeoTIFF tiles" test "$(requests 'GET /mapserv\?map=city.*FORMAT=image(%2[fF]|/)tiff')" -ge 1

# The same views.
run render-file render "$city/file.json" --views "$city/views.json" --out "$DIR/file" --k 4
expect_clean render-file 0
tiles=$(requests 'GET /elevation/wmts/1.0.0/dtm/')
run eval-wmts eval "$city/wmts.json" --views "$city/views.json" --truth "$DIR/file" --k 4 --json "$DIR/eval-wmts.json"
expect_clean eval-wmts 0
check "the views from the WMTS terrain as from the file (identical or >= 45 dB)" python3 - "$DIR/eval-wmts.json" <<'PY'
import json, sys
views = json.load(open(sys.argv[1]))["views"]
db = lambda v: float(v["psnr"]) if v["psnr"] is not None else float("inf")
print("  PSNR per view:", ", ".join(f'{v["view"]} {db(v):.2f} dB' for v in views))
sys.exit(0 if views and all(db(v) >= 45.0 for v in views) else 1)
PY
# The tiles of the first loads are in GDAL's tile cache (histoview's cache folder): none asked again.
check "a second load asks no tile again (GDAL's tile cache in the cache folder)" \
  test "$(requests 'GET /elevation/wmts/1.0.0/dtm/')" -eq "$tiles"
check "the tiles cached in the cache folder, not beside the data" \
  bash -c "test -d '$DIR/cache/gdal-wms' && ! test -e '$city/gdalwmscache' && ! test -e '$PWD/gdalwmscache'"

echo "$passed passed, $failed failed"
((failed == 0))
