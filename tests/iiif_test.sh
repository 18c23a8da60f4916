#!/usr/bin/env bash
# End-to-end test of photographs by URL and from a IIIF image service, against real servers on
# loopback (ctest: `iiif`, label "services"; docs/services.md, "Photographs by URL and IIIF").
#
#   tests/iiif_test.sh path/to/histoview [scratch-dir]
#
# Generates a small demo city, converts its photographs to tiled pyramidal TIFFs
# (tests/services/pyramid_tiff.py), serves them with tools/services.sh (lighttpd; iipsrv through
# FastCGI for the IIIF Image API 2; the folder under /files/), and checks that
#   - the views rendered with every photograph from IIIF score >= 30 dB against the same views
#     from the files (iipsrv re-encodes JPEG: not identical), and with every photograph and mask
#     by plain URL from /files/ are identical;
#   - the responses go into the response cache (HV_CACHE_DIR): a second run asks the server for no
#     photograph, HV_NO_CACHE=1 asks again;
#   - faults (a 404 info.json through tests/services/fault_proxy.py, a truncated IIIF image, a
#     missing plain image, an image of another aspect ratio) name the URL, the camera and the
#     status, leave that photograph out (exit code 3) and the rest renders.
# The stack and the proxy are stopped on exit, failure included. Without lighttpd or iipsrv: exit
# 77 (skipped) unless CI is set, where it fails. Prints "N passed, M failed".
set -uo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
source "$ROOT/tests/services/harness.sh" "$@"  # HV, DIR; checks, runs, clean-up

for tool in lighttpd python3 timeout; do command -v "$tool" >/dev/null || missing "$tool not found"; done
[[ -x ${HV_IIPSRV:-/usr/lib/iipimage-server/iipsrv.fcgi} ]] || missing "iipsrv not found (iipimage-server)"
[[ -x ${HV_MAPSERV:-/usr/lib/cgi-bin/mapserv} ]] || missing "mapserv not found (cgi-mapserver)"

# --- the city, its photographs as pyramidal TIFFs, the stack
run demo demo --out "$DIR" --generate-only --buildings 6 --photos 6 --views 2
expect_clean demo 0
mkdir -p "$city/iiif"
ids=$(python3 -c 'import json,sys; print(" ".join(c["id"] for c in json.load(open(sys.argv[1]))["cameras"]))' "$city/cameras.json")
for id in $ids; do
  python3 "$ROOT/tests/services/pyramid_tiff.py" "$city/images/$id.png" "$city/iiif/$id.tif" &
  while (($(jobs -rp | wc -l) >= 2)); do sleep 0.1; done
done
wait
check "photographs converted to tiled pyramidal TIFFs" test "$(ls "$city/iiif" | wc -l)" -eq "$(wc -w <<<"$ids")"
stack_up
state=$(sed -n 's/.*(state: \(.*\))$/\1/p' "$DIR/up.out")
first=${ids%% *}
check "iipsrv answers a IIIF 2 info.json" python3 - "$URL/iiif?IIIF=$first.tif/info.json" <<'PY'
import json, sys, urllib.request
with urllib.request.urlopen(sys.argv[1], timeout=10) as r:
    info = json.load(r)
sys.exit(0 if "iiif.io/api/image/2" in info["@context"] and info["width"] > 0 else 1)
PY

# cameras NAME PATTERN [MASKS] [ONLY] [OVERRIDE_IMAGE]: a cameras file and a scene beside the
# city's files whose images are PATTERN with {id} replaced (masks likewise with MASKS); with ONLY,
# only that camera's image is replaced (by OVERRIDE_IMAGE when given).
cameras() {
  python3 - "$city" "$@" <<'PY'
import json, sys
city, name, pattern = sys.argv[1:4]
masks = sys.argv[4] if len(sys.argv) > 4 else ""
only = sys.argv[5] if len(sys.argv) > 5 else ""
doc = json.load(open(f"{city}/cameras.json"))
for c in doc["cameras"]:
    if only and c["id"] != only:
        continue
    c["image"] = pattern.replace("{id}", c["id"])
    if masks and c.get("mask"):
        c["mask"] = masks.replace("{id}", c["id"])
json.dump(doc, open(f"{city}/cameras-{name}.json", "w"), indent=1)
json.dump({"crs": "EPSG:2154", "terrain": {"path": "dtm.tif"},
           "buildings": {"path": "buildings.geojson", "height": "height"},
           "cameras": {"path": f"cameras-{name}.json"}}, open(f"{city}/{name}.json", "w"), indent=1)
PY
}
cameras files "images/{id}.png"
cameras iiif "$URL/iiif?IIIF={id}.tif/info.json"
cameras http "$URL/files/images/{id}.png" "$URL/files/masks/{id}.png"

# --- the same views from the files, from IIIF and by URL
run render-files render "$city/files.json" --views "$city/views.json" --out "$DIR/files" --k 4
expect_clean render-files 0
psnr() {  # psnr REPORT MIN: every view at >= MIN dB ("inf": identical)
  python3 - "$1" "$2" <<'PY'
import json, sys
views = json.load(open(sys.argv[1]))["views"]
db = lambda v: float(v["psnr"]) if v["psnr"] is not None else float("inf")
print("  PSNR per view:", ", ".join(f'{v["view"]} {db(v):.2f} dB' for v in views))
sys.exit(0 if views and all(db(v) >= float(sys.argv[2]) for v in views) else 1)
PY
}
# lighttpd buffers its access log; SIGHUP (its log rotation) writes the buffer out. A check of the
# log first asks for that, then looks for up to 10 s.
flush_log() { kill -HUP "$(cat "$state/lighttpd.pid")" 2>/dev/null; sleep 0.5; }
logged() {
  flush_log
  for _ in $(seq 20); do grep -q "$1" "$state/access.log" && return 0; sleep 0.5; done
  return 1
}
requests() { flush_log; grep -c "$1" "$state/access.log"; }
run eval-iiif eval "$city/iiif.json" --views "$city/views.json" --truth "$DIR/files" --k 4 --json "$DIR/eval-iiif.json"
expect_clean eval-iiif 0
check "IIIF: the views as from the files (PSNR >= 30 dB; JPEG re-encoded by iipsrv)" psnr "$DIR/eval-iiif.json" 30
first_width=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["cameras"][0]["width"])' "$city/cameras.json")
check "IIIF: the image asked at the camera's size ($first_width px wide, Image API 2 'w,')" \
  logged "IIIF=$first.tif/full/$first_width,/0/default.jpg"
run eval-http eval "$city/http.json" --views "$city/views.json" --truth "$DIR/files" --k 4 --json "$DIR/eval-http.json"
expect_clean eval-http 0
check "plain URLs (photographs and masks from /files/): identical to the files" psnr "$DIR/eval-http.json" 1e308
check "masks fetched by URL" logged "GET /files/masks/"

# --- the response cache: a second run asks the server for nothing; HV_NO_CACHE=1 asks again
check "responses cached in HV_CACHE_DIR/responses" test -n "$(ls -A "$DIR/cache/responses" 2>/dev/null)"
before=$(requests "IIIF=")
run eval-iiif-cached eval "$city/iiif.json" --views "$city/views.json" --truth "$DIR/files" --k 4 --json "$DIR/eval-cached.json"
expect_clean eval-iiif-cached 0
check "cached: no IIIF request the second time ($before before, $(requests "IIIF=") after)" test "$(requests "IIIF=")" -eq "$before"
HV_NO_CACHE=1 run eval-iiif-nocache eval "$city/iiif.json" --views "$city/views.json" --truth "$DIR/files" --k 4 --json "$DIR/eval-nocache.json"
check "HV_NO_CACHE=1: asked again" test "$(requests "IIIF=")" -gt "$before"

# --- faults: the photograph named and left out, the rest rendered
pport=$(free_port)
python3 "$ROOT/tests/services/fault_proxy.py" "$pport" "$URL" "$DIR/proxy.log" >"$DIR/proxy.out" 2>&1 &
proxy_pid=$!
for _ in $(seq 50); do grep -q "fault proxy on" "$DIR/proxy.out" 2>/dev/null && break; sleep 0.1; done
P=http://127.0.0.1:$pport
# The first camera that is not square, for the square photograph below.
second=$(python3 -c 'import json,sys; print(next(c["id"] for c in json.load(open(sys.argv[1]))["cameras"] if c["width"] != c["height"]))' "$city/cameras.json")
# A square photograph for a 4:3 camera: refused by its aspect ratio (a 64 x 64 grey PNG, then
# its pyramid).
python3 - "$DIR/square.png" <<'PY'
import struct, sys, zlib
raw = b"".join(b"\x00" + bytes([128]) * 64 for _ in range(64))
chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
open(sys.argv[1], "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 64, 64, 8, 0, 0, 0, 0))
                             + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
PY
python3 "$ROOT/tests/services/pyramid_tiff.py" "$DIR/square.png" "$city/iiif/square.tif"
cases=(
  "404-info $first $P/404/iiif?IIIF=$first.tif/info.json HTTP error code ?: ?404"
  "truncated-image $first $P/truncated-data/iiif?IIIF=$first.tif/info.json transfer closed|truncated|cannot decode"
  "missing-url $first $URL/files/images/none.png HTTP error code ?: ?404"
  "aspect $second $URL/iiif?IIIF=square.tif/info.json aspect ratios disagree"
)
for c in "${cases[@]}"; do
  read -r name id image _ <<<"$c"
  cameras "fault-$name" "$image" "" "$id"
  (
    t0=$SECONDS
    timeout -k 5 "$RUN_LIMIT" "$HV" render "$city/fault-$name.json" --views "$city/views.json" --out "$DIR/fault-$name" --k 4 \
      >"$DIR/fault-$name.out" 2>&1
    echo "$? $((SECONDS - t0))" >"$DIR/fault-$name.status"
  ) &
  while (($(jobs -rp | wc -l) >= 3)); do sleep 0.2; done
done
wait_faults $((RUN_LIMIT + 10)) "${cases[@]}"
for c in "${cases[@]}"; do
  read -r name id image why <<<"$c"
  [[ -s $DIR/fault-$name.status ]] || { fail "fault $name: the run never ended"; continue; }
  read -r rc secs <"$DIR/fault-$name.status"
  out=$DIR/fault-$name.out
  expect_clean "fault $name" 3
  url_re=$(sed 's/[][\.*^$?+(){}|]/\\&/g' <<<"${image%%\?*}")
  expect_out "fault $name names the camera and the URL" "camera '$id'.*$url_re"
  expect_out "fault $name says why" "$why"
  check "fault $name: the views still rendered" test "$(ls "$DIR/fault-$name"/*.png 2>/dev/null | wc -l)" -ge 2
done

echo "$passed passed, $failed failed"
((failed == 0))
