#!/usr/bin/env bash
# End-to-end test of points from 3D Tiles served over HTTP (ctest: `tiles3d`, label "services";
# docs/services.md, "Points from 3D Tiles").
#
#   tests/tiles3d_test.sh path/to/histoview [scratch-dir]
#
# Generates a small demo city, writes its lidar points as a tileset (`histoview points-tiles`),
# serves the folder with tools/services.sh (lighttpd on 127.0.0.1, the folder under /files/) and
# checks that
#   - `"points": {"tileset": "http://…/tileset.json", "tolerance": 0}` reads every tile and gives the
#     LAS file's points: the same count, the same bounds within 2 cm (ECEF and back, 16-bit
#     quantization over each tile's box);
#   - with the default tolerance (2 px from the photographs' cameras) no more tiles or points than
#     the whole (all of them: the cameras are close), with 200 px fewer;
#   - a tile answered 404 is named with its URL and status and left out, the rest loads (exit 3).
# The stack is stopped on exit, failure included. Without lighttpd or mapserv: exit 77 (skipped)
# unless CI is set, where it fails. Prints "N passed, M failed".
set -uo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
source "$ROOT/tests/services/harness.sh" "$@"  # HV, DIR; checks, runs, clean-up, missing, stack_up
for tool in lighttpd python3 timeout; do command -v "$tool" >/dev/null || missing "$tool not found"; done
[[ -x ${HV_MAPSERV:-/usr/lib/cgi-bin/mapserv} ]] || missing "mapserv not found (cgi-mapserver)"


run demo demo --out "$DIR" --generate-only --buildings 4 --photos 4 --views 1
expect_clean demo 0
run points-tiles points-tiles "$city/points.las" "$city/tiles" --points-per-tile 4000
expect_clean points-tiles 0
expect_out points-tiles "wrote .*tileset.json: [0-9]+ points"
# The same tileset with one tile missing (the server answers 404).
cp -r "$city/tiles" "$city/tiles-404"
gone=$(cd "$city/tiles-404" && ls r?*.pnts | head -1)
rm -f "$city/tiles-404/$gone"

stack_up

scene() {  # scene NAME POINTS_ENTRY
  printf '{"crs": "EPSG:2154", "points": %s, "cameras": {"path": "cameras.json"}}\n' "$2" >"$city/$1.json"
}
count() { sed -n 's/^points  *\([0-9]*\).*/\1/p' "$1"; }
bounds() { sed -n 's/^  bounds *//p' "$1" | tr -d '(),.' | tr -s ' ' '\n' | grep -v '^$' | head -6 | tr '\n' ' '; }
scene las '{"path": "points.las"}'
scene all "{\"tileset\": \"$URL/files/tiles/tileset.json\", \"tolerance\": 0}"
scene sse "{\"tileset\": \"$URL/files/tiles/tileset.json\"}"
scene coarse "{\"tileset\": \"$URL/files/tiles/tileset.json\", \"tolerance\": 200}"
scene missing "{\"tileset\": \"$URL/files/tiles-404/tileset.json\", \"tolerance\": 0}"

run las info "$city/las.json"
expect_clean las 0
las_out=$out
run all info "$city/all.json"
expect_clean all 0
all_out=$out
n_las=$(count "$las_out")
n_all=$(count "$all_out")
check "every tile: $n_all points, as the LAS file ($n_las)" test -n "$n_all" -a "$n_all" = "$n_las" -a "${n_las:-0}" -gt 0
check "every tile: the LAS file's bounds within 2 cm" python3 - "$las_out" "$all_out" <<'PY'
import re, sys
def bounds(path):
    for line in open(path):
        if line.strip().startswith("bounds"):
            return [float(v) for v in re.findall(r"-?\d+\.\d+", line)]
a, b = bounds(sys.argv[1]), bounds(sys.argv[2])
worst = max(abs(x - y) for x, y in zip(a, b))
print(f"      largest bound difference {worst * 1000:.1f} mm")
sys.exit(0 if len(a) == 6 and len(b) == 6 and worst < 0.02 else 1)
PY
expect_out all "3d tiles ([0-9]+) tiles read of \\1 in the tileset"
tiles_all=$(sed -n 's/^  3d tiles \([0-9]*\) tiles read of \([0-9]*\).*/\2/p' "$all_out")

run sse info "$city/sse.json"
expect_clean sse 0
n_sse=$(count "$out")
read_sse=$(sed -n 's/^  3d tiles \([0-9]*\) tiles read.*/\1/p' "$out")
check "by screen-space error: $read_sse of $tiles_all tiles, $n_sse of $n_las points" \
  test -n "$n_sse" -a "${n_sse:-0}" -gt 0 -a "${n_sse:-0}" -le "${n_las:-0}" -a "${read_sse:-0}" -le "${tiles_all:-0}"
grep "3d tiles" "$out" | sed 's/^/      /'
# A coarser tolerance reads fewer tiles (the demo's cameras stand within 100 m of every point, so
# the default 2 px reads them all).
run coarse info "$city/coarse.json"
expect_clean coarse 0
n_coarse=$(count "$out")
read_coarse=$(sed -n 's/^  3d tiles \([0-9]*\) tiles read.*/\1/p' "$out")
check "tolerance 200 px: $read_coarse of $tiles_all tiles, $n_coarse points" \
  test -n "$n_coarse" -a "${read_coarse:-0}" -gt 0 -a "${read_coarse:-0}" -lt "${tiles_all:-0}" -a "${n_coarse:-0}" -lt "${n_las:-0}"

run missing info "$city/missing.json"
expect_clean missing 3
expect_out missing "$URL/files/tiles-404/$gone: points tile: HTTP error code : 404 \\(tile root[^ ]* left out\\)"
# ... and listed among what is missing (docs/services.md "What is missing"), by its URL.
expect_out missing "^missing +point tile: $URL/files/tiles-404/$gone: points tile: HTTP error code : 404"
n_missing=$(count "$out")
check "a 404 tile left out, the rest loads: $n_missing of $n_las points" \
  test -n "$n_missing" -a "${n_missing:-0}" -gt 0 -a "${n_missing:-0}" -lt "${n_las:-0}"

echo "$passed passed, $failed failed"
((failed == 0))
