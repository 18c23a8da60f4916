#!/usr/bin/env bash
# The demo city's orthophoto served as WMTS by MapCache (ctest: `orthophoto_wmts`, label
# "services"; docs/services.md, "An orthophoto by WMTS"):
#
#   tests/orthophoto_wmts_test.sh path/to/histoview [scratch-dir]
#
# Generates a small demo city (it writes orthophoto.tif), serves it with tools/services.sh
# (lighttpd on 127.0.0.1, MapCache's WMTS over a GDAL source reading the file), and checks that a
# top-down view renders the same from `"orthophoto": {"path": "WMTS:http://…"}` as from the file
# (PSNR >= 35 dB over the view; measured 38.9 dB: docs/services.md), that the orthophoto shows
# there at all (against --no-orthophoto), that `info` reports it, and that an unreachable WMTS
# leaves it out with a warning naming the URL, the scene rendering shaded. The stack is stopped on
# exit, failure included. Exit 77 (skipped) when lighttpd, MapServer or MapCache is missing, unless
# CI is set: then it fails. Prints "N passed, M failed".
set -uo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
source "$ROOT/tests/services/harness.sh" "$@"  # HV, DIR; checks, runs, clean-up

for tool in lighttpd python3 timeout; do command -v "$tool" >/dev/null || missing "$tool not found"; done
[[ -x ${HV_MAPSERV:-/usr/lib/cgi-bin/mapserv} ]] || missing "mapserv not found (cgi-mapserver)"
[[ -x ${HV_MAPCACHE:-/usr/lib/cgi-bin/mapcache} ]] || missing "mapcache not found (mapcache-cgi)"

run demo demo --out "$DIR" --generate-only --buildings 8 --photos 12 --views 3
expect_clean demo 0
check "the demo wrote orthophoto.tif and named it in scene.json" \
  grep -q '"orthophoto"' "$city/scene.json"
stack_up
state=$(sed -n 's/^serving .* (state: \(.*\))$/\1/p' "$DIR/up.out")
WMTS="WMTS:$URL/mapcache/wmts?SERVICE=WMTS&REQUEST=GetCapabilities"

# The demo's scene with its orthophoto from the file, from the WMTS, and from a port nobody
# listens on; a view straight down over the whole city, 320 x 240.
python3 - "$city" "$WMTS" "http://127.0.0.1:$(free_port)" <<'PY'
import json, sys
city, wmts, dead = sys.argv[1:]
scene = json.load(open(f"{city}/scene.json"))
for name, path in (("file", "orthophoto.tif"), ("wmts", wmts), ("dead", "WMTS:" + dead + "/wmts?SERVICE=WMTS&REQUEST=GetCapabilities")):
    s = dict(scene, orthophoto={"path": path})
    json.dump(s, open(f"{city}/scene-{name}.json", "w"), indent=1)
json.dump({"cameras": [{"id": "top", "width": 320, "height": 240, "focal": [300, 300], "principal": [160, 120],
                        "skew": 0.0, "center": [651000.0, 6862000.0, 160.0],
                        "rotation": [1, 0, 0, 0, -1, 0, 0, 0, -1]}]}, open(f"{city}/top.json", "w"), indent=1)
PY

run info-wmts info "$city/scene-wmts.json"
expect_clean info-wmts 0
expect_out info-wmts "orthophoto [0-9]+ x [0-9]+ px, [0-9.]+ m per pixel, [0-9]+ bytes"
for name in file wmts; do
  run "render-$name" render "$city/scene-$name.json" --views "$city/top.json" --out "$DIR/$name" --k 4
  expect_clean "render-$name" 0
done
run render-off render "$city/scene-file.json" --views "$city/top.json" --out "$DIR/off" --k 4 --no-orthophoto
expect_clean render-off 0
compare() { python3 "$ROOT/tests/services/png_compare.py" "$@" >"$DIR/compare.out" 2>&1; local rc=$?; sed 's/^/      /' "$DIR/compare.out"; return $rc; }
at_least() { compare "$1" "$2" --min-pixels 5000 && python3 -c 'import sys; t = open(sys.argv[1]).read().split()[1]; sys.exit(0 if t == "inf" or float(t) >= float(sys.argv[2]) else 1)' "$DIR/compare.out" "$3"; }
below() { compare "$1" "$2" --min-pixels 5000 && python3 -c 'import sys; t = open(sys.argv[1]).read().split()[1]; sys.exit(0 if t != "inf" and float(t) < float(sys.argv[2]) else 1)' "$DIR/compare.out" "$3"; }
# `render` writes RGB PNGs: the comparison is over the whole view, the photographs' pixels (the
# same in both) included.
check "WMTS: the view as from the file (PSNR >= 35 dB)" at_least "$DIR/file/top.png" "$DIR/wmts/top.png" 35
check "the orthophoto shows: the file's render differs from --no-orthophoto (PSNR < 25 dB)" \
  below "$DIR/file/top.png" "$DIR/off/top.png" 25
flush_log() { kill -HUP "$(cat "$state/lighttpd.pid")" 2>/dev/null; sleep 0.5; }
flush_log
tiles=$(grep -c "GET /mapcache/wmts/1.0.0/orthophoto/" "$state/access.log")
check "tiles fetched by GetTile (REST): $tiles, bounded (at most 64 a run, 3 runs)" test "$tiles" -ge 1 -a "$tiles" -le 192

# An unreachable WMTS: a warning naming the URL, the orthophoto left out, the picture as with
# --no-orthophoto.
HV_LOG=warn run render-dead render "$city/scene-dead.json" --views "$city/top.json" --out "$DIR/dead" --k 4
expect_clean render-dead 0
expect_out render-dead "orthophoto.path.*(orthophoto left out: untextured terrain shaded)"
check "an unreachable WMTS renders as --no-orthophoto" at_least "$DIR/off/top.png" "$DIR/dead/top.png" 1e308

echo "$passed passed, $failed failed"
((failed == 0))
