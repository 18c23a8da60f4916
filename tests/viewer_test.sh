#!/usr/bin/env bash
# End-to-end test of the desktop viewer (ctest: `viewer`, labels "viewer" and "gl").
#
#   tests/viewer_test.sh path/to/histoview [scratch-dir] [part]
#
# part: picture, timeline, thennow or ui (the sections below, in that order), or all (the
# default). ctest runs the four parts as four tests (viewer_picture, …), each on its own demo
# city, so that they run side by side.
#
# Generates a small demo city, opens `histoview view` on it under Xvfb at a held-out view camera,
# lets it converge (progressive frames until every selected image is resident with a current
# depth map) and takes a screenshot of the window, then renders the same camera with
# `histoview render` and compares the two pictures. Then the same for two debug views
# (docs/viewer.md): the weight of the photograph nearest the view with the frusta drawn, and that
# photograph's depth map, against `render --debug weight:ID --frusta` and `--debug depth:ID`.
# Then the timeline (--timeline FROM:TO, positions along it): a window holding no photograph
# gives the untextured picture, one holding all the full one, each against `render --from --to`;
# and then and now at a photograph's camera: at opacity 1 the window is the photograph itself, with
# a swipe line at the middle its left half and, right of the line, the render without it.
# Then the traffic played (--traffic-play, docs/traffic.md): its clock moves from --time.
# Then the map (--map): a click on a photograph's dot (xdotool) goes to that photograph; the wheel
# zooms about the pointer, a drag pans, a click on the zoomed map still goes there.
# Exits 77 (skipped) when xvfb-run or the viewer is not available, saying which.
set -uo pipefail

HV=${1:?usage: viewer_test.sh path/to/histoview [scratch-dir] [picture|timeline|thennow|ui|all]}
HV=$(cd "$(dirname "$HV")" && pwd)/$(basename "$HV")
DIR=${2:-$(mktemp -d "${TMPDIR:-/tmp}/hv-viewer-test.XXXXXX")}
PART=${3:-all}
case $PART in
  picture | timeline | thennow | ui | all) ;;
  *) echo "viewer_test.sh: unknown part '$PART' (expected picture, timeline, thennow, ui or all)"; exit 2 ;;
esac
part() { [[ $PART == all || $PART == "$1" ]]; }
source "$(dirname "$0")/viewer_common.sh"

# The held-out view, a window of its aspect ratio (320 pixels wide), and the photograph nearest to
# it (among the frame's images, so its weight view is not empty).
read -r id w h photo < <(python3 -c '
import json, sys
c = json.load(open(sys.argv[1]))["cameras"][0]
photos = json.load(open(sys.argv[2]))["cameras"]
d2 = lambda p: sum((a - b) ** 2 for a, b in zip(p["center"], c["center"]))
print(c["id"], 320, round(320 * c["height"] / c["width"]), min(photos, key=d2)["id"])' \
  "$city/views.json" "$city/cameras.json")
size=${w}x${h}

# PSNR over RGB between the two PNGs. The viewer runs the same renderer on the same camera and,
# once converged, the same images and depth maps, and the window shows the colour target through
# a same-size (nearest) blit, so the pictures should be identical (PSNR infinite). The bound,
# 50 dB (RMS error below one grey level in 255), leaves room only for a window framebuffer that
# would dither or convert colours; a flipped, shifted, rescaled or partially converged picture
# scores far below it (a one-row shift of the demo city is under 25 dB). The PNG reader is the
# services tests' (Python's standard library has none), under the name the scripts below import.
cat >"$DIR/png.py" <<EOF
import runpy
read_png = runpy.run_path("$(cd "$(dirname "$0")" && pwd)/services/png_read.py")["decode_png"]
EOF
cat >"$DIR/compare.py" <<'EOF'
import math, runpy, sys
read_png = runpy.run_path(sys.argv[0].rsplit("/", 1)[0] + "/png.py")["read_png"]

# Optional: argv[4:6] the columns [x0, x1) compared; argv[6] "differ": expect a PSNR below 30 dB.
wa, ha, ca, A = read_png(sys.argv[1])
wb, hb, cb, B = read_png(sys.argv[2])
if (wa, ha) != (wb, hb):
    print(f"FAIL: viewer screenshot is {wa}x{ha}, render {wb}x{hb}")
    sys.exit(1)
x0, x1 = (int(sys.argv[4]), int(sys.argv[5])) if len(sys.argv) > 5 else (0, wa)
differ = len(sys.argv) > 6 and sys.argv[6] == "differ"
se, n, differing = 0, 0, 0
for y in range(ha):
    for x in range(x0, x1):
        d = [A[y][x * ca + k] - B[y][x * cb + k] for k in range(3)]
        se += sum(v * v for v in d)
        differing += any(d)
        n += 3
mse = se / n
psnr = float("inf") if mse == 0 else 10 * math.log10(255 ** 2 / mse)
name = lambda p: "/".join(p.split("/")[-2:])
print(f"{name(sys.argv[1])} vs {name(sys.argv[2])} (columns {x0}..{x1 - 1}): "
      f"PSNR {psnr:.2f} dB, {differing} of {(x1 - x0) * ha} pixels differ")
if differ:
    if psnr >= 30.0:
        print("FAIL: expected different pictures (PSNR below 30 dB); images in", sys.argv[3])
        sys.exit(1)
    print("ok (they differ)")
    sys.exit(0)
if psnr < 50.0:
    print("FAIL: PSNR below 50 dB; images in", sys.argv[3])
    sys.exit(1)
print("ok")
EOF
compare() { python3 "$DIR/compare.py" "$@"; }

if part picture; then
# The viewer: -screen gives Xvfb a 24-bit visual (its default depth is 8 bits per channel too,
# but say it). --frames caps the run in case it never converges.
xvfb-run -a -s "-screen 0 1024x768x24" "$HV" view "$city/scene.json" --views "$city/views.json" --camera "$id" \
  --size "$size" --screenshot "$DIR/viewer.png" --exit-after-converge --frames 400 --hide-panel \
  --print-frame-times >"$DIR/view.out" 2>&1
rc=$?
if ((rc != 0)) || [[ ! -s $DIR/viewer.png ]]; then
  echo "FAIL: histoview view exited with $rc (or wrote no screenshot); output:"
  tail -30 "$DIR/view.out"
  exit 1
fi
grep -E "converged after|wrote" "$DIR/view.out"

"$HV" render "$city/scene.json" --views "$city/views.json" --size "$size" --out "$DIR/render" >"$DIR/render.out" 2>&1 ||
  { echo "FAIL: histoview render"; cat "$DIR/render.out"; exit 1; }

compare "$DIR/viewer.png" "$DIR/render/$id.png" "$DIR" || exit 1

# Debug views: the renderer draws them in place of the picture, so the viewer's screenshot of a
# converged debug view is `render`'s preview of it, under the same 50 dB bound.
for debug in "weight:$photo --frusta" "depth:$photo"; do
  read -r spec extra <<<"$debug"
  name=${spec%%:*}
  # shellcheck disable=SC2086 # $extra: zero or one option
  xvfb-run -a -s "-screen 0 1024x768x24" "$HV" view "$city/scene.json" --views "$city/views.json" --camera "$id" \
    --size "$size" --screenshot "$DIR/viewer-$name.png" --exit-after-converge --frames 400 --hide-panel \
    --debug "$spec" $extra >"$DIR/view-$name.out" 2>&1
  rc=$?
  if ((rc != 0)) || [[ ! -s $DIR/viewer-$name.png ]]; then
    echo "FAIL: histoview view --debug $spec exited with $rc (or wrote no screenshot); output:"
    tail -30 "$DIR/view-$name.out"
    exit 1
  fi
  # shellcheck disable=SC2086
  "$HV" render "$city/scene.json" --views "$city/views.json" --size "$size" --out "$DIR/render-$name" \
    --debug "$spec" $extra >"$DIR/render-$name.out" 2>&1 ||
    { echo "FAIL: histoview render --debug $spec"; cat "$DIR/render-$name.out"; exit 1; }
  [[ -s $DIR/render-$name/$id.$name.png ]] || { echo "FAIL: render --debug $spec wrote no $id.$name.png"; exit 1; }
  echo "debug view $spec $extra (photograph nearest the view):"
  compare "$DIR/viewer-$name.png" "$DIR/render-$name/$id.$name-preview.png" "$DIR" || exit 1
done

fi

if part timeline; then
# The timeline (src/hv/viewer/timeline.h): --timeline sets the window at two positions along it
# as dragging its handles does, the viewer prints the days and how many dated photographs the
# window holds, and the picture is `render --from --to` of those days. The count is checked here
# against the photographs' dates. The last day of the timeline (1:1, 31 December of the last
# bar's last year) holds none of the demo's photographs (dated on days 1..28), so the view is
# the shaded, untextured geometry; 0:1 holds every photograph: the picture of the first test.
count_in_window() {
  python3 -c '
import datetime, json, sys
first, last = (datetime.date.fromisoformat(d) for d in sys.argv[2:4])
dates = [c.get("date", "") for c in json.load(open(sys.argv[1]))["cameras"]]
print(sum(1 for d in dates if d and first <= datetime.date.fromisoformat(d) <= last))' "$@"
}
for positions in 1:1 0:0.5 0:1; do
  name=timeline-${positions/:/-}
  xvfb-run -a -s "-screen 0 1024x768x24" "$HV" view "$city/scene.json" --views "$city/views.json" --camera "$id" \
    --size "$size" --screenshot "$DIR/viewer-$name.png" --exit-after-converge --frames 400 --hide-panel \
    --timeline "$positions" >"$DIR/view-$name.out" 2>&1
  rc=$?
  line=$(grep -o "viewer: timeline .*" "$DIR/view-$name.out")
  if ((rc != 0)) || [[ ! -s $DIR/viewer-$name.png || -z $line ]]; then
    echo "FAIL: histoview view --timeline $positions exited with $rc (or wrote no screenshot or window); output:"
    tail -30 "$DIR/view-$name.out"
    exit 1
  fi
  read -r from _ to count _ <<<"${line#viewer: timeline }"  # "FROM .. TO: N of M dated photographs"
  to=${to%:}
  expected=$(count_in_window "$city/cameras.json" "$from" "$to")
  echo "timeline $positions: $from .. $to holds $count photograph(s) (by their dates: $expected)"
  if [[ $count != "$expected" ]]; then
    echo "FAIL: the viewer counts $count photograph(s) in $from .. $to, their dates $expected"
    exit 1
  fi
  case $positions in
    1:1) ((count == 0)) || { echo "FAIL: the timeline's last day should hold no demo photograph"; exit 1; } ;;
    0:1) ((count == 12)) || { echo "FAIL: the whole timeline should hold the 12 photographs"; exit 1; } ;;
  esac
  "$HV" render "$city/scene.json" --views "$city/views.json" --size "$size" --out "$DIR/render-$name" \
    --from "$from" --to "$to" >"$DIR/render-$name.out" 2>&1 ||
    { echo "FAIL: histoview render --from $from --to $to"; cat "$DIR/render-$name.out"; exit 1; }
  compare "$DIR/viewer-$name.png" "$DIR/render-$name/$id.png" "$DIR" || exit 1
done
# The whole timeline is the picture without a window (the first part's render, made here when
# this part runs alone).
if [[ ! -s $DIR/render/$id.png ]]; then
  "$HV" render "$city/scene.json" --views "$city/views.json" --size "$size" --out "$DIR/render" >"$DIR/render.out" 2>&1 ||
    { echo "FAIL: histoview render"; cat "$DIR/render.out"; exit 1; }
fi
echo "an empty window is not the textured picture:"
compare "$DIR/viewer-timeline-1-1.png" "$DIR/render/$id.png" "$DIR" 0 "$w" differ || exit 1
compare "$DIR/viewer-timeline-0-1.png" "$DIR/render/$id.png" "$DIR" || exit 1

fi

if part thennow; then
# Then and now (src/hv/viewer/then_now.h) at the photograph nearest the view, the window its
# size: at opacity 1 the photograph covers the window 1:1, so the screenshot is its PNG. With a
# swipe line at 0.5 the columns left of the line (pixel centres below w / 2) are the photograph's,
# those right of it the render at its camera without it (`render --camera ID --exclude ID`).
read -r pw ph < <(python3 -c '
import json, sys
c = next(c for c in json.load(open(sys.argv[1]))["cameras"] if c["id"] == sys.argv[2])
print(c["width"], c["height"])' "$city/cameras.json" "$photo")
for mode in "--then-now-opacity 1" "--then-now-swipe 0.5" "--then-now-opacity 0.5"; do
  read -r option value <<<"$mode"
  name=${option#--}-$value
  xvfb-run -a -s "-screen 0 1600x1200x24" "$HV" view "$city/scene.json" --camera "$photo" --size "${pw}x${ph}" \
    --screenshot "$DIR/viewer-$name.png" --exit-after-converge --frames 400 --hide-panel "$option" "$value" \
    >"$DIR/view-$name.out" 2>&1
  rc=$?
  if ((rc != 0)) || [[ ! -s $DIR/viewer-$name.png ]]; then
    echo "FAIL: histoview view --camera $photo $mode exited with $rc (or wrote no screenshot); output:"
    tail -30 "$DIR/view-$name.out"
    exit 1
  fi
done
"$HV" render "$city/scene.json" --camera "$photo" --exclude "$photo" --size "${pw}x${ph}" --out "$DIR/render-loo" \
  >"$DIR/render-loo.out" 2>&1 || { echo "FAIL: histoview render --camera $photo --exclude $photo"; cat "$DIR/render-loo.out"; exit 1; }
loo=$(ls "$DIR"/render-loo/*.png | grep -v -- "-preview" | head -1)
half=$((pw / 2))  # columns 0..half-1 have centres below pw / 2
echo "then and now at $photo (${pw}x${ph}):"
compare "$DIR/viewer-then-now-opacity-1.png" "$city/images/$photo.png" "$DIR" || exit 1
compare "$DIR/viewer-then-now-swipe-0.5.png" "$city/images/$photo.png" "$DIR" 0 "$half" || exit 1
compare "$DIR/viewer-then-now-swipe-0.5.png" "$loo" "$DIR" "$half" "$pw" || exit 1
# At opacity 0.5 each pixel is a * photograph + (1 - a) * render, a = round(0.5 * 255) / 255 (the
# alpha an 8-bit vertex colour carries; compositeThenNow in then_now.h), rounded: within one grey
# level (the GL blend of 8-bit colours may round the other way).
cat >"$DIR/blend.py" <<'EOF'
import runpy, sys
read_png = runpy.run_path(sys.argv[0].rsplit("/", 1)[0] + "/png.py")["read_png"]
w, h, cv, V = read_png(sys.argv[1])
_, _, cp, P = read_png(sys.argv[2])
_, _, cr, R = read_png(sys.argv[3])
a = round(float(sys.argv[4]) * 255) / 255
worst = max(abs(V[y][x * cv + k] - round(a * P[y][x * cp + k] + (1 - a) * R[y][x * cr + k]))
            for y in range(h) for x in range(w) for k in range(3))
print(f"opacity {sys.argv[4]}: largest difference from a * photograph + (1 - a) * render: {worst}")
sys.exit(1 if worst > 1 else 0)
EOF
python3 "$DIR/blend.py" "$DIR/viewer-then-now-opacity-0.5.png" "$city/images/$photo.png" "$loo" 0.5 ||
  { echo "FAIL: then and now at opacity 0.5 is not that blend; images in $DIR"; exit 1; }

fi

if part ui; then
# The control panel, whose render-settings widgets are made from the settings schema
# (src/hv/viewer/desktop/settings_panel.cpp): drawn with its Blending, Points and Debug sections
# open (--points, --debug), every frame until convergence, and in the screenshot. A widget that
# breaks Dear ImGui's ID or disabled-state stacks aborts on its assertions.
xvfb-run -a -s "-screen 0 1024x768x24" "$HV" view "$city/scene.json" --views "$city/views.json" --camera "$id" \
  --size 640x480 --screenshot "$DIR/viewer-panel.png" --screenshot-ui --exit-after-converge --frames 400 \
  --points --frusta --debug count >"$DIR/view-panel.out" 2>&1
rc=$?
if ((rc != 0)) || [[ ! -s $DIR/viewer-panel.png ]]; then
  echo "FAIL: histoview view with the panel exited with $rc (or wrote no screenshot); output:"
  tail -30 "$DIR/view-panel.out"
  exit 1
fi
echo "the panel of the render settings: drawn, $(grep -o 'converged after [0-9]* frame(s)' "$DIR/view-panel.out")"

# The panel's Sources section (src/hv/viewer/desktop/sources_panel.cpp) for a scene whose
# buildings file is missing: drawn (open, with the panel in the screenshot) and its lines printed,
# naming the buildings' path; the rest renders.
python3 - "$city/scene.json" "$city/scene-missing.json" <<'PY'
import json, sys
doc = json.load(open(sys.argv[1]))
doc["buildings"]["path"] = "none.geojson"
json.dump(doc, open(sys.argv[2], "w"), indent=1)
PY
xvfb-run -a -s "-screen 0 1024x768x24" "$HV" view "$city/scene-missing.json" --views "$city/views.json" --camera "$id" \
  --size 640x480 --screenshot "$DIR/viewer-missing.png" --screenshot-ui --exit-after-converge --frames 400 \
  >"$DIR/view-missing.out" 2>&1
rc=$?
if ((rc != 0)) || [[ ! -s $DIR/viewer-missing.png ]] ||
  ! grep -q "^viewer: sources: missing buildings: $city/none.geojson: " "$DIR/view-missing.out"; then
  echo "FAIL: histoview view of a scene without its buildings file exited with $rc, or its Sources panel did not"
  echo "list them ('viewer: sources: missing buildings: $city/none.geojson: ...'); output:"
  tail -30 "$DIR/view-missing.out"
  exit 1
fi
echo "the Sources panel: $(grep -m1 '^viewer: sources: missing' "$DIR/view-missing.out")"

# Key taps shorter than a frame (src/hv/viewer/key_events.h): the viewer redraws every frame at
# 1024x768 on a software renderer (frames of tens to hundreds of milliseconds) and F2 is tapped
# three times, each held 12 ms. Read as key events, every tap is a screenshot, numbered without
# overwriting (histoview-screenshot-001.png …); polled once per frame, a tap is seen only when a
# poll falls inside its 12 ms, and three in a row almost never are.
if command -v xdotool >/dev/null; then
  taps=$DIR/taps
  mkdir -p "$taps"
  xvfb-run -a -s "-screen 0 1280x1024x24" bash -c '
    cd "$1" || exit 1
    "$2" view "$3/scene.json" --size 1024x768 --redraw --frames 100000 --hide-panel --print-frame-times \
      >view.out 2>&1 &
    pid=$!
    for _ in $(seq 300); do grep -q "^frame 3:" view.out && break; sleep 0.2; done
    win=$(xdotool search --name "^histoview" | head -1)
    [[ -n $win ]] && xdotool windowfocus "$win" 2>/dev/null
    for _ in 1 2 3; do xdotool keydown F2; sleep 0.012; xdotool keyup F2; sleep 0.8; done
    # The taps are read in the frames that follow (seconds each on a loaded machine).
    for _ in $(seq 300); do [[ -e histoview-screenshot-003.png ]] && break; sleep 0.2; done
    sleep 1
    kill "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
    exit 0' _ "$taps" "$HV" "$city"
  shots=$(ls "$taps"/histoview-screenshot-00[1-3].png 2>/dev/null | wc -l)
  frame_ms=$(grep -o "^frame [0-9]*: [0-9.]* ms" "$taps/view.out" | tail -1)
  if ((shots != 3)); then
    echo "FAIL: three 12 ms taps of F2 wrote $shots numbered screenshot(s) (last $frame_ms); output:"
    tail -20 "$taps/view.out"
    exit 1
  fi
  echo "three 12 ms taps of F2: three numbered screenshots ($frame_ms)"
else
  echo "(key taps not tested: xdotool is not installed; tools/install-deps.sh installs it)"
fi

# The map (M; --map opens it): a click on a photograph's dot goes to that photograph. The viewer
# prints where it draws each dot (window pixels) whenever the map moves; xdotool clicks the dot
# farthest from the others, and the viewer must name that photograph as the one it goes to. Then
# four wheel notches up on that dot zoom the map by 2 about it (every distance between dots doubles,
# the dot stays under the pointer along the side the map fills), a drag moves every dot by the same amount without going
# anywhere, and a click on the dot where it is now goes to it again.
if command -v xdotool >/dev/null; then
  mapdir=$DIR/map
  mkdir -p "$mapdir"
  # The dots printed after byte FROM of view.out, the last position of each: "INDEX X Y" lines.
  cat >"$mapdir/dots.py" <<'EOF'
import re, sys
text = open("view.out").read()[int(sys.argv[1]) if len(sys.argv) > 1 else 0:]
dots = {}
for m in re.finditer(r"viewer: map: photograph (\d+) at ([-\d.e]+) ([-\d.e]+)", text):
    dots[int(m.group(1))] = (float(m.group(2)), float(m.group(3)))
for i, (x, y) in sorted(dots.items()):
    print(i, x, y)
EOF
  # The drag: 30 and 20 pixels from the dot away from the dots' centroid (the map can pan that way).
  cat >"$mapdir/drag.py" <<'EOF'
import sys
x, y = float(sys.argv[1]), float(sys.argv[2])
d = [tuple(map(float, l.split()[1:])) for l in open("zoomed.txt")]
cx, cy = sum(p[0] for p in d) / len(d), sum(p[1] for p in d) / len(d)
print(30 if x >= cx else -30, 20 if y >= cy else -20)
EOF
  xvfb-run -a -s "-screen 0 1280x1024x24" bash -c '
    cd "$1" || exit 1
    "$2" view "$3/scene.json" --size 1024x768 --redraw --frames 100000 --hide-panel --map --print-frame-times \
      >view.out 2>&1 &
    pid=$!
    for _ in $(seq 300); do grep -q "viewer: map: photograph" view.out && break; sleep 0.2; done
    sleep 1
    win=$(xdotool search --name "^histoview" | head -1)
    [[ -n $win ]] && xdotool windowfocus "$win" 2>/dev/null
    read -r index x y < <(python3 -c "
import re, sys
dots = {}
for m in re.finditer(r\"viewer: map: photograph (\\d+) at ([-\\d.e]+) ([-\\d.e]+)\", open(\"view.out\").read()):
    dots[int(m.group(1))] = (float(m.group(2)), float(m.group(3)))
gap = lambda i: min([((dots[i][0] - p[0]) ** 2 + (dots[i][1] - p[1]) ** 2) ** 0.5 for j, p in dots.items() if j != i] or [1e9])
i = max(dots, key=gap)
print(i, round(dots[i][0]), round(dots[i][1]))")
    echo "$index" >clicked
    if [[ -n $win && -n $x ]]; then
      # From outside the window into it (Dear ImGui follows the pointer once it has entered).
      xdotool mousemove 1270 1010; sleep 0.5
      xdotool mousemove --window "$win" "$x" "$y"; sleep 1
      xdotool click 1
      for _ in $(seq 150); do grep -q "viewer: map: to photograph" view.out && break; sleep 0.2; done
      # Each step waits for two frames (slow ones under load see several events at once).
      waitframes() {
        local n=$(($(grep -c "^frame" view.out) + $1))
        for _ in $(seq 300); do (($(grep -c "^frame" view.out) >= n)) && break; sleep 0.1; done
      }
      waitframes 2
      python3 dots.py >before.txt
      from=$(stat -c %s view.out)
      for _ in 1 2 3 4; do xdotool click 4; sleep 0.1; done
      waitframes 2
      python3 dots.py "$from" >zoomed.txt
      read -r dx dy < <(python3 drag.py "$x" "$y")
      echo "$dx $dy" >drag
      from=$(stat -c %s view.out)
      xdotool mousedown 1; waitframes 2
      for s in 1 2 3 4 5 6 7 8 9 10; do
        xdotool mousemove --window "$win" $((x + dx * s / 10)) $((y + dy * s / 10)); sleep 0.05
      done
      waitframes 2; xdotool mouseup 1; waitframes 2
      python3 dots.py "$from" >panned.txt
      read -r nx ny < <(python3 -c "import sys
for l in open(\"panned.txt\"):
    i, px, py = l.split()
    if i == sys.argv[1]: print(round(float(px)), round(float(py)))" "$index")
      if [[ -n $nx ]]; then
        xdotool mousemove --window "$win" "$nx" "$ny"; waitframes 2
        xdotool click 1
        for _ in $(seq 150); do (($(grep -c "viewer: map: to photograph" view.out) >= 2)) && break; sleep 0.2; done
      fi
    fi
    kill "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
    exit 0' _ "$mapdir" "$HV" "$city"
  clicked=$(cat "$mapdir/clicked" 2>/dev/null)
  if [[ -z $clicked ]] || ! grep -q "viewer: map: to photograph $clicked " "$mapdir/view.out"; then
    echo "FAIL: a click on photograph ${clicked:-?}'s dot on the map did not go to it; output:"
    grep -v "^frame" "$mapdir/view.out" | tail -20
    exit 1
  fi
  grep "viewer: map: to photograph" "$mapdir/view.out" | head -1
  # Zoom (factor 2 = 2^(4/4), hv::viewer::wheelZoomFactor) and pan against the printed dots.
  if ! python3 - "$mapdir" "$clicked" <<'EOF'; then
import itertools, math, sys
d, clicked = sys.argv[1], int(sys.argv[2])
read = lambda f: {int(l.split()[0]): tuple(map(float, l.split()[1:])) for l in open(f"{d}/{f}")}
before, zoomed, panned = read("before.txt"), read("zoomed.txt"), read("panned.txt")
drag = tuple(map(float, open(f"{d}/drag").read().split()))
assert zoomed and panned and zoomed.keys() == before.keys() == panned.keys(), "the dots were not printed again"
ratios = [math.dist(zoomed[i], zoomed[j]) / math.dist(before[i], before[j])
          for i, j in itertools.combinations(before, 2) if math.dist(before[i], before[j]) > 20]
# The dot stays under the pointer along the side the whole map fills; along the other the map is
# kept on its extent (MapZoom's limits) and may shift.
stay = min(abs(zoomed[clicked][k] - before[clicked][k]) for k in (0, 1))
print(f"map zoom: distances x {min(ratios):.3f} to {max(ratios):.3f}, the pointed dot moved "
      f"{zoomed[clicked][0] - before[clicked][0]:.2f}, {zoomed[clicked][1] - before[clicked][1]:.2f} px")
assert all(abs(r - 2.0) < 0.02 for r in ratios), "four wheel notches should scale the map by 2"
assert stay < 1.5, "the dot under the pointer should stay there"
shifts = [(panned[i][0] - zoomed[i][0], panned[i][1] - zoomed[i][1]) for i in zoomed]
s0 = shifts[0]
print(f"map drag of {drag}: dots moved by {s0[0]:.1f}, {s0[1]:.1f}")
assert all(math.dist(s, s0) < 0.5 for s in shifts), "a drag moves every dot by the same amount"
assert math.hypot(*s0) > 5 and all(s * g >= 0 and abs(s) <= abs(g) + 1 for s, g in zip(s0, drag)), \
    "the dots should follow the drag (up to the map's edge)"
EOF
    echo "FAIL: the map's zoom or pan (above)"
    exit 1
  fi
  if (($(grep -c "viewer: map: to photograph $clicked " "$mapdir/view.out") != 2)); then
    echo "FAIL: a click on photograph $clicked's dot on the zoomed and panned map did not go to it (once)"
    grep "viewer: map:" "$mapdir/view.out" | tail -5
    exit 1
  fi
  echo "a click on the zoomed and panned map goes to photograph $clicked"
fi

# The traffic played (hv/viewer/traffic_clock.h): from --time 5 at 10 simulated seconds a second,
# a few frames later the clock has moved on (and stays inside the SUMO run's 0 .. 59.5 s, looping).
if grep -q '"traffic"' "$city/scene.json"; then
  xvfb-run -a -s "-screen 0 1024x768x24" "$HV" view "$city/scene.json" --views "$city/views.json" --camera "$id" \
    --size "$size" --frames 8 --hide-panel --time 5 --traffic-play 10 >"$DIR/view-traffic.out" 2>&1
  rc=$?
  t=$(grep -o "viewer: traffic at [0-9.e+-]* s" "$DIR/view-traffic.out" | awk '{print $4}')
  if ((rc != 0)) || [[ -z $t ]] || ! python3 -c 'import sys; t = float(sys.argv[1]); sys.exit(0 if 5 < t <= 59.5 else 1)' "$t"; then
    echo "FAIL: histoview view --time 5 --traffic-play 10 exited with $rc, traffic at '${t}' s (expected past 5 s); output:"
    tail -20 "$DIR/view-traffic.out"
    exit 1
  fi
  echo "traffic played from 5 s at 10x for 8 frames: at $t s"
else
  echo "(traffic play not tested: the demo city has no traffic, SUMO is not installed)"
fi
fi
