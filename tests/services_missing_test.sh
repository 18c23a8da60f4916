#!/usr/bin/env bash
# What is missing, said by the frame's commands (ctest: `services_missing`, label "services";
# docs/services.md "What is missing"): a scene whose buildings come from a WFS that fails (404,
# 500 on its GetFeature, a reset connection; tests/services/fault_proxy.py in front of the local
# stack, 127.0.0.1 only) and whose terrain comes from the WCS loads and renders with the terrain;
# `info` lists the missing buildings with their URL and the reason, `render` writes its views and
# ends with a one-line summary naming them, and the viewer (under Xvfb, when there is one) prints
# its Sources panel's lines naming them.
#
#   tests/services_missing_test.sh path/to/histoview [scratch-dir]
#
# Exit 77 (skipped) when lighttpd or MapServer is missing, unless CI is set. Prints "N passed, M failed".
set -uo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
source "$ROOT/tests/services/harness.sh" "$@"  # HV, DIR; checks, runs, clean-up

for tool in lighttpd python3 timeout; do command -v "$tool" >/dev/null || missing "$tool not found"; done
[[ -x ${HV_MAPSERV:-/usr/lib/cgi-bin/mapserv} ]] || missing "mapserv not found (cgi-mapserver)"

run demo demo --out "$DIR" --generate-only --buildings 8 --photos 12 --views 3
expect_clean demo 0
stack_up
WCS="WCS:$URL/mapserv?map=city&SERVICE=WCS&VERSION=2.0.1&COVERAGEID=dtm"

pport=$(free_port)
python3 "$ROOT/tests/services/fault_proxy.py" "$pport" "$URL" "$DIR/proxy.log" >"$DIR/proxy.out" 2>&1 &
proxy_pid=$!
for _ in $(seq 50); do grep -q "fault proxy on" "$DIR/proxy.out" 2>/dev/null && break; sleep 0.1; done
check "fault proxy started" grep -q "fault proxy on" "$DIR/proxy.out"
P=http://127.0.0.1:$pport

# A regular expression matching the text $1 as it is.
literal() { printf '%s' "$1" | sed 's/[][\.*^$+?(){}|/]/\\&/g'; }

viewer=1
command -v xvfb-run >/dev/null || viewer=0
"$HV" view --help 2>&1 | grep -q "not in this build" && viewer=0
((viewer)) || echo "note: no viewer run (xvfb-run or the viewer is missing)"

for f in 404 500-data reset; do
  wfs="WFS:$P/$f/mapserv?map=city&TYPENAME=ms:buildings"
  printf '{"crs": "EPSG:2154", "cameras": {"path": "cameras.json"}, "terrain": {"path": "%s"},
 "buildings": {"path": "%s", "height": "height"}}\n' "$WCS" "$wfs" >"$city/missing-$f.json"
  url=$(literal "$wfs")

  run "info-$f" info "$city/missing-$f.json"
  expect_clean "info-$f" 3
  expect_out "info $f: terrain read" "terrain +[1-9][0-9]* vertices"
  expect_out "info $f: lists the missing buildings with their URL and the reason" "^missing +buildings: $url: .+"

  run "render-$f" render "$city/missing-$f.json" --views "$city/views.json" --out "$DIR/render-$f" --k 4
  expect_clean "render-$f" 3
  check "render $f: the views are written" test "$(ls "$DIR/render-$f"/*.png 2>/dev/null | wc -l)" -eq 3
  expect_out "render $f: one line names what is missing" "^missing: buildings \\($url\\)$"

  if ((viewer)); then
    # Under Xvfb (`run` runs histoview itself), as tests/viewer_test.sh does.
    timeout -k 5 "$RUN_LIMIT" xvfb-run -a -s "-screen 0 640x480x24" "$HV" view "$city/missing-$f.json" \
      --size 320x240 --frames 200 --exit-after-converge --hide-panel >"$DIR/view-$f.out" 2>&1
    rc=$?
    out=$DIR/view-$f.out
    expect_clean "view-$f" any
    expect_out "view $f: the Sources panel lists the missing buildings" "^viewer: sources: missing buildings: $url: .+"
    expect_out "view $f: and what the WCS sent at load" "^viewer: sources: read terrain from .*COVERAGEID=dtm: [1-9][0-9]* response"
  fi
done

echo "$passed passed, $failed failed"
((failed == 0))
