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
#   - a progressive flight over one view (`fly --progressive`) shows the previews (a quarter of
#     the camera's width here) first and converges to the full images, as the view from the files (>= 30 dB); the bytes
#     fetched are printed, the previews' under a quarter of the full images';
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

# --- the fault proxy (tests/services/fault_proxy.py), for the slow link and the faults below
pport=$(free_port)
# 8 KiB/s for the throttled link below.
HV_FAULT_RATE=8192 python3 "$ROOT/tests/services/fault_proxy.py" "$pport" "$URL" "$DIR/proxy.log" >"$DIR/proxy.out" 2>&1 &
proxy_pid=$!
for _ in $(seq 50); do grep -q "fault proxy on" "$DIR/proxy.out" 2>/dev/null && break; sleep 0.1; done
P=http://127.0.0.1:$pport

# --- previews (a small size first): a progressive flight over one view, every response fetched
# (HV_NO_CACHE=1) through a slow link (the fault proxy's `throttled-data`, 8 KiB/s: on loopback
# alone the full images arrive before a preview is ever drawn, and at 16 KiB/s, 1.2 s for the
# four, they did so too when the first frame was slow). A preview (about 2.5 KB) then takes 0.3 s
# and a full image (about 18 KB) 2.3 s, within the harness's 5 s time-out. fly draws its frames as
# fast as it can, not in real time, so the path must hold enough frames for the four full images
# to arrive even one after the other (9 s): it lasts 40 s (601 frames, 26 ms each on a quiet
# machine with a program per shading configuration: 15.6 s; 12 s, 4.8 s of frames, was too short). The first frame that
# shows photographs shows their previews (asked by width, "W,"), the converged frame the full
# images, as the views from the files.
cameras throttled "$P/throttled-data/iiif?IIIF={id}.tif/info.json"
python3 - "$city/views.json" "$DIR/path.json" <<'PY'
import json, sys
view = json.load(open(sys.argv[1]))["cameras"][0]
json.dump({"cameras": [dict(view, id="a", t=0), dict(view, id="b", t=40)]}, open(sys.argv[2], "w"))
PY
view_id=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["cameras"][0]["id"])' "$city/views.json")
flush_log
log_before=$(wc -l <"$state/access.log")
HV_LOG=debug HV_NO_CACHE=1 run fly-previews fly "$city/throttled.json" --path "$DIR/path.json" --fps 15 --progressive \
  --out "$DIR/fly" --k 4
expect_clean fly-previews 0
frames=$(grep -E '^.*frame [0-9]+ \(progressive\): ' "$out" | sed -E 's/.*frame ([0-9]+) \(progressive\): ([0-9]+) images shown, ([0-9]+) as previews, ([0-9]+) waiting/\1 \2 \3 \4/')
first_shown=$(awk '$2 > 0 {print; exit}' <<<"$frames")
last_frame=$(tail -1 <<<"$frames")
echo "  first frame with photographs (frame, shown, previews, waiting): $first_shown; last: $last_frame"
check "previews: the first frame with photographs shows them all as previews" \
  awk -v l="$first_shown" 'BEGIN { split(l, f, " "); exit !(f[2] > 0 && f[3] == f[2]) }'
check "previews: the last frame shows no preview and waits for nothing" \
  awk -v l="$last_frame" 'BEGIN { split(l, f, " "); exit !(f[2] > 0 && f[3] == 0 && f[4] == 0) }'
expect_out "previews: the flight converged" "first converged frame: [0-9]+"
flush_log
tail -n +"$((log_before + 1))" "$state/access.log" >"$DIR/fly-access.log"
# The preview's width: the image fitted in min(256, a quarter of the camera's longer side).
first_height=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["cameras"][0]["height"])' "$city/cameras.json")
box=$(( (first_width > first_height ? first_width : first_height) / 4 )); box=$((box < 256 ? box : 256))
preview_width=$(python3 -c 'import sys; w, h, b = map(int, sys.argv[1:]); print(min(b, w) if w >= h else max(1, round(b * w / h)))' "$first_width" "$first_height" "$box")
check "previews: each photograph asked at $preview_width px wide ('$preview_width,') before the full size ('$first_width,')" \
  python3 - "$DIR/fly-access.log" "$first_width" "$preview_width" <<'PY'
import re, sys
full, preview = sys.argv[2], sys.argv[3]
first = {}  # (photograph, width) -> first line asking for it
for i, line in enumerate(open(sys.argv[1])):
    m = re.search(r"IIIF=([^/ ]+)\.tif/full/(\d+),/0/default\.jpg", line)
    if m:
        first.setdefault((m.group(1), m.group(2)), i)
fulls = [p for (p, w) in first if w == full]
print("  photographs asked at full size:", " ".join(sorted(fulls)))
sys.exit(0 if fulls and all(first.get((p, preview), 1 << 30) < first[(p, full)] for p in fulls) else 1)
PY
last_png=$(ls "$DIR/fly"/*.png | sort | tail -1)
check "previews: the converged frame as the view from the files (PSNR >= 30 dB)" \
  python3 - "$ROOT/tests/services/png_compare.py" "$last_png" "$DIR/files/$view_id.png" <<'PY'
import re, subprocess, sys
out = subprocess.run([sys.executable] + sys.argv[1:], capture_output=True, text=True).stdout
print("  converged frame against the files:", out.strip())
m = re.search(r"PSNR (\S+) dB", out)
sys.exit(0 if m and (m.group(1) == "inf" or float(m.group(1)) >= 30) else 1)
PY
fetched=$(grep -E '^photographs read by URL:' "$out")
echo "  $fetched"
echo "  $(grep -E '^http\(s\) responses:' "$out")"
echo "  $(grep -E '^first frame after' "$out")"
check "previews: bytes reported, the previews' under a quarter of the full images'" python3 - "$fetched" <<'PY'
import re, sys
m = re.search(r"(\d+) previews, (\d+) bytes; (\d+) full images, (\d+) bytes", sys.argv[1])
sys.exit(0 if m and int(m.group(1)) > 0 and int(m.group(3)) > 0 and 0 < 4 * int(m.group(2)) < int(m.group(4)) else 1)
PY

# --- faults: the photograph named and left out, the rest rendered
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
  expect_out "fault $name: render's summary names the missing photograph" "^missing: photograph \\($url_re"
  check "fault $name: the views still rendered" test "$(ls "$DIR/fault-$name"/*.png 2>/dev/null | wc -l)" -ge 2
done

echo "$passed passed, $failed failed"
((failed == 0))
