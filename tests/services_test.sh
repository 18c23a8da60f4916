#!/usr/bin/env bash
# End-to-end test of service-backed scenes against real servers on loopback (ctest: `services`,
# label "services"; docs/services.md).
#
#   tests/services_test.sh path/to/histoview [scratch-dir]
#
# Generates a small demo city, serves it with tools/services.sh (lighttpd + MapServer on
# 127.0.0.1), and checks that
#   - the same views render to the same picture from the files and from the services (terrain from
#     WCS 2.0.1, buildings from WFS 2.0 or OGC API - Features, cameras from the local file; and
#     cameras from WFS 2.0, exported by `histoview cameras export --ogr`): PSNR >= 45 dB or
#     identical;
#   - each fault of tests/services/fault_proxy.py (404, 500, 503, slow, reset, truncated,
#     malformed) gives a partial scene, a message naming the URL, bounded retries, no hang (each
#     run under `timeout`) and no crash (an exit code, not a signal).
# The stack and the proxy are stopped on exit, failure included. Exit 77 (skipped) when lighttpd
# or MapServer is missing, unless CI is set: then it fails. Prints "N passed, M failed".
set -uo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
source "$ROOT/tests/services/harness.sh" "$@"  # HV, DIR; checks, runs, clean-up

for tool in lighttpd python3 timeout; do command -v "$tool" >/dev/null || missing "$tool not found"; done
[[ -x ${HV_MAPSERV:-/usr/lib/cgi-bin/mapserv} ]] || missing "mapserv not found (cgi-mapserver)"

export HV_FAULT_SLOW_S=12  # the slow fault's delay: past GDAL_HTTP_TIMEOUT (harness.sh)

# --- the city and the stack
run demo demo --out "$DIR" --generate-only --buildings 8 --photos 12 --views 3
expect_clean demo 0
# The cameras as a point layer for the WFS (tools/services.sh serves cameras.gpkg when present).
printf '{"crs": "EPSG:2154", "cameras": {"path": "cameras.json"}}\n' >"$city/cameras-file.json"
run cameras-export cameras export "$city/cameras-file.json" --ogr "$city/cameras.gpkg"
expect_clean cameras-export 0
stack_up
WCS="WCS:$URL/mapserv?map=city&SERVICE=WCS&VERSION=2.0.1&COVERAGEID=dtm"
WFS="WFS:$URL/mapserv?map=city&TYPENAME=ms:buildings"
OAPIF="OAPIF:$URL/mapserv/city/ogcapi/collections/buildings"

# The stack binds to loopback only, and answers with CORS headers.
check "lighttpd listens on 127.0.0.1 only" python3 - "$port" <<'PY'
import socket, sys
port = int(sys.argv[1])
addrs = set()
for line in open("/proc/net/tcp").read().splitlines()[1:] + open("/proc/net/tcp6").read().splitlines()[1:]:
    f = line.split()
    local, state = f[1], f[3]
    if state == "0A" and int(local.split(":")[1], 16) == port:
        addrs.add(local.split(":")[0])
sys.exit(0 if addrs == {"0100007F"} else 1)
PY
check "responses carry Access-Control-Allow-Origin: *" python3 - "$URL/mapserv?map=city&SERVICE=WFS&REQUEST=GetCapabilities" <<'PY'
import sys, urllib.request
with urllib.request.urlopen(sys.argv[1], timeout=10) as r:
    sys.exit(0 if r.headers.get("Access-Control-Allow-Origin") == "*" and r.status == 200 else 1)
PY

# scene NAME TERRAIN BUILDINGS [CAMERAS]: a scene.json beside the city's files (cameras: the local
# file, else the OGR source CAMERAS).
scene() {
  python3 - "$city/$1.json" "$2" "$3" "${4:-}" <<'PY'
import json, sys
path, terrain, buildings, cameras = sys.argv[1:5]
doc = {"crs": "EPSG:2154", "cameras": {"path": "cameras.json"}}
if cameras: doc["cameras"] = {"path": cameras, "format": "ogr", "layer": "ms:cameras"}
if terrain: doc["terrain"] = {"path": terrain}
if buildings: doc["buildings"] = {"path": buildings, "height": "height"}
json.dump(doc, open(path, "w"), indent=1)
PY
}

# --- the same views from files and from services
scene files dtm.tif buildings.geojson
scene wfs "$WCS" "$WFS"
scene oapif "$WCS" "$OAPIF"
scene wfs-cameras dtm.tif buildings.geojson "WFS:$URL/mapserv?map=city&TYPENAME=ms:cameras"
run render-files render "$city/files.json" --views "$city/views.json" --out "$DIR/files" --k 4
expect_clean render-files 0
# psnr_ok FILE: every view of an eval report at >= 45 dB or identical (infinite PSNR).
psnr_ok() {
  python3 - "$1" <<'PY'
import json, sys
views = json.load(open(sys.argv[1]))["views"]
db = lambda v: float(v["psnr"]) if v["psnr"] is not None else float("inf")  # "inf": identical
bad = [v["view"] for v in views if not db(v) >= 45.0]
print("  PSNR per view:", ", ".join(f'{v["view"]} {db(v):.2f} dB' for v in views))
sys.exit(0 if views and not bad else 1)
PY
}
for s in wfs oapif wfs-cameras; do
  run "eval-$s" eval "$city/$s.json" --views "$city/views.json" --truth "$DIR/files" --k 4 --json "$DIR/eval-$s.json"
  expect_clean "eval-$s" 0
  check "$s: same picture as from files (PSNR >= 45 dB or identical)" psnr_ok "$DIR/eval-$s.json"
done
run info-wfs info "$city/wfs.json"
expect_clean info-wfs 0
expect_out info-wfs "buildings +[1-9][0-9]* triangles"
expect_out info-wfs "terrain +[1-9][0-9]* vertices"
# What OGR asked the WFS: paged GetFeature requests with a bounding-box filter (one per tile).
state=$(sed -n 's/.*(state: \(.*\))$/\1/p' "$DIR/up.out")
# lighttpd buffers its access log: SIGHUP makes it write what it holds (and reopen the file).
kill -HUP "$(cat "$state/lighttpd.pid")" 2>/dev/null
sleep 0.5
check "WFS GetFeature is paged (STARTINDEX, COUNT)" grep -q "REQUEST=GetFeature.*STARTINDEX=0&COUNT=" "$state/access.log"
check "cameras read from the WFS" grep -qiE "REQUEST=GetFeature.*TYPENAMES?=ms(:|%3A)cameras" "$state/access.log"
check "WFS GetFeature carries a BBOX filter" grep -q "REQUEST=GetFeature.*FILTER=.*BBOX" "$state/access.log"

# Whole files by URL (read through GDAL's HTTP client): the lidar points from /files/, the same
# count as from the file; a missing one is named with its HTTP status.
printf '{"crs": "EPSG:2154", "points": {"path": "%s"}}\n' "$URL/files/points.las" >"$city/points-url.json"
printf '{"crs": "EPSG:2154", "points": {"path": "points.las"}}\n' >"$city/points-file.json"
printf '{"crs": "EPSG:2154", "points": {"path": "%s"}}\n' "$URL/files/none.las" >"$city/points-404.json"
run points-url info "$city/points-url.json"
expect_clean points-url 0
points_url=$(sed -n 's/^points  *\([0-9]*\).*/\1/p' "$out")
run points-file info "$city/points-file.json"
points_file=$(sed -n 's/^points  *\([0-9]*\).*/\1/p' "$out")
check "points by URL: $points_url points, as from the file ($points_file)" test -n "$points_url" -a "$points_url" = "$points_file" -a "${points_url:-0}" -gt 0
run points-404 info "$city/points-404.json"
expect_clean points-404 3
expect_out points-404 "$URL/files/none.las: HTTP error code : 404 \\(points left out\\)"

# --- faults, through the proxy: /<fault>/... is forwarded to the stack and spoilt
pport=$(free_port)
python3 "$ROOT/tests/services/fault_proxy.py" "$pport" "$URL" "$DIR/proxy.log" >"$DIR/proxy.out" 2>&1 &
proxy_pid=$!
for _ in $(seq 50); do grep -q "fault proxy on" "$DIR/proxy.out" 2>/dev/null && break; sleep 0.1; done
check "fault proxy started" grep -q "fault proxy on" "$DIR/proxy.out"
P=http://127.0.0.1:$pport

# fault_start NAME SOURCE FAULT [KIND]: starts one case in the background. SOURCE is "terrain"
# (WCS) or "buildings" (WFS, or OAPIF with KIND=oapif) through the proxy, the other source served
# directly. The cases run side by side (most of their time is spent waiting on time-outs), each
# under `timeout`; fault_check then checks it: the scene loads partially, names the URL, neither
# hangs nor crashes.
fault_start() {
  local name=$1 source=$2 f=$3 kind=${4:-wfs}
  local t=$WCS b=$WFS
  case $source:$kind in
    terrain:*) t="WCS:$P/$f/mapserv?map=city&SERVICE=WCS&VERSION=2.0.1&COVERAGEID=dtm" ;;
    buildings:wfs) b="WFS:$P/$f/mapserv?map=city&TYPENAME=ms:buildings" ;;
    buildings:oapif) b="OAPIF:$P/$f/mapserv/city/ogcapi/collections/buildings" ;;
  esac
  scene "fault-$name" "$t" "$b"
  (
    t0=$SECONDS
    timeout -k 5 "$RUN_LIMIT" "$HV" info "$city/fault-$name.json" >"$DIR/fault-$name.out" 2>&1
    echo "$? $((SECONDS - t0))" >"$DIR/fault-$name.status"
  ) &
}
fault_check() {
  local name=$1 source=$2 f=$3
  read -r rc secs <"$DIR/fault-$name.status"
  out=$DIR/fault-$name.out
  expect_clean "fault $name" any
  expect_out "fault $name names the URL" "127\\.0\\.0\\.1:$pport/$f/"
  if [[ $source == terrain ]]; then
    expect_out "fault $name: terrain left out" "terrain left out|terrain +0 vertices"
    expect_out "fault $name: partial scene (buildings kept)" "buildings +[1-9][0-9]* triangles"
  else
    expect_out "fault $name: buildings left out" "buildings left out|left out\\)|buildings +0 triangles"
    expect_out "fault $name: partial scene (terrain kept)" "terrain +[1-9][0-9]* vertices"
  fi
}
cases=(
  "wfs-slow buildings slow"
  "wfs-404 buildings 404"
  "wfs-500-data buildings 500-data"
  "wcs-503 terrain 503"
  "wfs-reset buildings reset"
  "wfs-truncated-data buildings truncated-data"
  "wfs-malformed-data buildings malformed-data"
  "oapif-malformed-data buildings malformed-data oapif"
  "wcs-malformed-data terrain malformed-data"
  "wcs-truncated-data terrain truncated-data"
)
# Two at a time (the proxy is the third job): more slowed the stack itself past the time-out on
# the shared 2-core machine.
for c in "${cases[@]}"; do
  while (($(jobs -rp | wc -l) >= 3)); do sleep 0.2; done
  fault_start $c
done
wait_faults $((RUN_LIMIT + 30)) "${cases[@]}"
for c in "${cases[@]}"; do
  read -r name source f _ <<<"$c"
  if [[ -s $DIR/fault-$name.status ]]; then fault_check "$name" "$source" "$f"
  else fail "fault $name: no status (the run never ended)"; fi
done
# Bounded retries: GDAL asks again on 503 (GDAL_HTTP_MAX_RETRY=2), then gives up: no request was
# sent more than 1 + 2 times.
check "503: at most 1 + GDAL_HTTP_MAX_RETRY tries of one request" python3 - "$DIR/proxy.log" <<'PY'
import collections, sys
n = collections.Counter(l for l in open(sys.argv[1]) if l.startswith("503 "))
print("  tries per request:", max(n.values()) if n else 0)
sys.exit(0 if n and 2 <= max(n.values()) <= 3 else 1)
PY
read -r _ slow_secs <"$DIR/fault-wfs-slow.status"
check "slow: given up within the time-outs and their retries (${slow_secs}s)" test "$slow_secs" -le 40

echo "$passed passed, $failed failed"
((failed == 0))
