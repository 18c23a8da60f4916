#!/usr/bin/env bash
# The cache of service responses and the progress of loading from services, against real servers
# on loopback (ctest: `services_cache`, label "services"; docs/services.md, "Cache", "Progress"):
#
#   tests/services_cache_test.sh path/to/histoview [scratch-dir]
#
# Generates a small demo city, serves it with tools/services.sh (lighttpd + MapServer on
# 127.0.0.1), and checks that
#   - loading a scene from the WFS (or OGC API - Features) and the WCS prints a line of progress
#     per request (the tile, the request, its size, the features so far);
#   - a second load of the same scene sends no request at all to the services (lighttpd's access
#     log), renders the same views, and says its responses came from the cache;
#   - HV_NO_CACHE=1 asks the services again;
#   - under a cap smaller than the responses (HV_CACHE_MAX_MB), the cache folder stays under it
#     and the scene still loads.
# The stack is stopped on exit, failure included. Exit 77 (skipped) when lighttpd or MapServer is
# missing, unless CI is set: then it fails. Prints "N passed, M failed".
set -uo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
source "$ROOT/tests/services/harness.sh" "$@"  # HV, DIR; checks, runs, clean-up

for tool in lighttpd python3 timeout; do command -v "$tool" >/dev/null || missing "$tool not found"; done
[[ -x ${HV_MAPSERV:-/usr/lib/cgi-bin/mapserv} ]] || missing "mapserv not found (cgi-mapserver)"

run demo demo --out "$DIR" --generate-only --buildings 8 --photos 12 --views 3
expect_clean demo 0
stack_up
state=$(sed -n 's/^serving .* (state: \(.*\))$/\1/p' "$DIR/up.out")
WCS="WCS:$URL/mapserv?map=city&SERVICE=WCS&VERSION=2.0.1&COVERAGEID=dtm"
WFS="WFS:$URL/mapserv?map=city&TYPENAME=ms:buildings"
OAPIF="OAPIF:$URL/mapserv/city/ogcapi/collections/buildings"
for s in wfs:$WFS oapif:$OAPIF; do
  printf '{"crs": "EPSG:2154", "terrain": {"path": "%s"}, "buildings": {"path": "%s", "height": "height"}, "cameras": {"path": "cameras.json"}}\n' \
    "$WCS" "${s#*:}" >"$city/${s%%:*}.json"
done

# requests REGEX: lines of lighttpd's access log that match (flushed first: lighttpd buffers it).
requests() {
  kill -HUP "$(cat "$state/lighttpd.pid")" 2>/dev/null
  sleep 0.5
  grep -cE "$1" "$state/access.log"
}
DATA='REQUEST=GetFeature|REQUEST=GetCoverage|/items\?'
# loaded NAME: what `info` says of the buildings and the terrain.
loaded() { grep -E "^(buildings|terrain) " "$DIR/$1.out"; }

# psnr_ok FILE: every view of an eval report identical (infinite PSNR) or at >= 45 dB.
psnr_ok() {
  python3 - "$1" <<'PY'
import json, sys
views = json.load(open(sys.argv[1]))["views"]
db = lambda v: float(v["psnr"]) if v["psnr"] is not None else float("inf")
print("  PSNR per view:", ", ".join(f'{v["view"]} {db(v):.2f} dB' for v in views))
sys.exit(0 if views and all(db(v) >= 45.0 for v in views) else 1)
PY
}

# The first load renders the held-out views (`info` and `check` keep the loader quiet: their report
# says it all); the second scores the same views against the first's pictures.
for s in wfs oapif; do
  data_request=GetFeature
  [[ $s == oapif ]] && data_request=items
  before=$(requests "GET /mapserv")
  HV_LOG=info run "$s-first" render "$city/$s.json" --views "$city/views.json" --out "$DIR/$s-first" --k 4
  expect_clean "$s-first" 0
  expect_out "$s-first" "^loading buildings from ${s^^}:$URL.*: tile 1 of [0-9]+: $data_request, [0-9]+ (bytes|KB) \\([0-9]+ features so far\\)$"
  # (the terrain is the same WCS for both sources: from the cache the second time round)
  expect_out "$s-first" "^loading terrain from WCS:$URL.*: GetCoverage, [0-9]+ (bytes|KB|MB)( from the cache)?$"
  first=$(requests "GET /mapserv")
  data=$(requests "$DATA")
  check "$s: the first load asks the services ($((first - before)) requests, $data for features and coverages so far)" \
    test "$first" -gt "$before" -a "$data" -gt 0
  HV_LOG=info run "$s-second" eval "$city/$s.json" --views "$city/views.json" --truth "$DIR/$s-first" --k 4 \
    --json "$DIR/$s-second.json"
  expect_clean "$s-second" 0
  second=$(requests "GET /mapserv")
  check "$s: the second load sends no request ($first before it, $second after)" test "$second" -eq "$first"
  check "$s: the second load renders the same views (identical or >= 45 dB)" psnr_ok "$DIR/$s-second.json"
  expect_out "$s-second" "^loading buildings from .*: $data_request, [0-9]+ (bytes|KB) from the cache"
  expect_out "$s-second" "^loading terrain from .*: GetCoverage, .* from the cache"
done
run wfs-info info "$city/wfs.json"
expect_clean wfs-info 0
expect_out wfs-info "buildings +[1-9][0-9]* triangles"

# HV_NO_CACHE=1: every request sent again.
before=$(requests "$DATA")
HV_NO_CACHE=1 run wfs-nocache info "$city/wfs.json"
expect_clean wfs-nocache 0
after=$(requests "$DATA")
check "HV_NO_CACHE=1: features and coverage asked again ($before before, $after after)" test "$after" -gt "$before"
check "HV_NO_CACHE=1: the same buildings and terrain" diff <(loaded wfs-info) <(loaded wfs-nocache)

# The cap: the responses of one load take more than 24 KiB (measured above); under a cap of 24 KiB
# the folder stays under it, and the scene loads all the same.
total=$(du -sb "$DIR/cache/responses" | cut -f1)
check "the responses of the loads above take $total bytes, over the 24 KiB cap tried next" test "$total" -gt 24576
HV_CACHE_DIR=$DIR/capped HV_CACHE_MAX_MB=0.0234375 run wfs-capped info "$city/wfs.json"
expect_clean wfs-capped 0
# The cap holds the responses and GDAL's tile cache together (gdal-wcs/, the WCS driver's
# descriptions, is outside it).
capped=$(find "$DIR/capped/responses" "$DIR/capped/gdal-wms" -type f ! -name '*.tmp*' -printf '%s\n' 2>/dev/null |
  awk '{t += $1} END {print t + 0}')
kept=$(find "$DIR/capped/responses" -type f | wc -l)
check "under a cap of 24576 bytes the cache holds $capped bytes in $kept responses" test "$capped" -le 24576 -a "$kept" -gt 0
check "under the cap: the same buildings and terrain" diff <(loaded wfs-info) <(loaded wfs-capped)

echo "$passed passed, $failed failed"
((failed == 0))
