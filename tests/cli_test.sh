#!/usr/bin/env bash
# End-to-end test of the histoview command line (ctest: `cli`, label "cli").
#
#   tests/cli_test.sh path/to/histoview [scratch-dir]
#
# Generates a small demo city, then checks info / render / eval on it and on broken inputs. Every
# failing command must fail cleanly: a non-zero exit code < 128 and a message, never a signal.
# Prints "N passed, M failed" and exits non-zero when something failed.
set -uo pipefail   # no -e: most checks run commands that are meant to fail

HV=${1:?usage: cli_test.sh path/to/histoview [scratch-dir]}
HV=$(cd "$(dirname "$HV")" && pwd)/$(basename "$HV")
DIR=${2:-$(mktemp -d "${TMPDIR:-/tmp}/hv-cli-test.XXXXXX")}
rm -rf "$DIR"
mkdir -p "$DIR"
export HV_LOG=${HV_LOG:-error}

passed=0
failed=0
pass() { passed=$((passed + 1)); echo "ok    $*"; }
fail() { failed=$((failed + 1)); echo "FAIL  $*"; }
check() {  # check DESCRIPTION COMMAND...: the command must succeed
  local what=$1; shift
  if "$@"; then pass "$what"; else fail "$what"; fi
}

# run NAME ARGS...: runs histoview, output in $DIR/NAME.out (stdout + stderr), exit code in $rc.
run() {
  local name=$1; shift
  "$HV" "$@" >"$DIR/$name.out" 2>&1
  rc=$?
  out="$DIR/$name.out"
}
# run_capped NAME COMMAND...: runs COMMAND (not only histoview) in a 3 GiB address space
# (RLIMIT_AS), output and status as `run`. Under AddressSanitizer, which reserves terabytes of
# address space for its shadow memory, without the limit (and says so).
asan_build=0
if ldd "$HV" 2>/dev/null | grep -q libasan || nm -C "$HV" 2>/dev/null | grep -q __asan_init; then asan_build=1; fi
run_capped() {
  local name=$1; shift
  if ((asan_build)); then
    echo "note: $name runs without the 3 GiB address-space limit (AddressSanitizer)" >&2
    "$@" >"$DIR/$name.out" 2>&1
  else
    (ulimit -v 3145728; exec "$@") >"$DIR/$name.out" 2>&1
  fi
  rc=$?
  out="$DIR/$name.out"
}
# expect_rc NAME WANT: WANT is a number or "fail" (1..127). A signal (>= 128) or a sanitizer
# report is always a failure.
expect_rc() {
  local name=$1 want=$2 ok=1
  if ((rc >= 128)) || grep -qE "Segmentation|AddressSanitizer|runtime error:|terminate called|Aborted" "$out"; then
    ok=0
  elif [[ $want == fail ]]; then ((rc >= 1 && rc < 128)) || ok=0
  else ((rc == want)) || ok=0
  fi
  if ((ok)); then pass "$name: exit code $rc"; else
    fail "$name: exit code $rc (expected $want); output:"
    sed 's/^/      /' "$out" | tail -20
  fi
}
# expect_out NAME REGEX: the output of the last run matches (grep -E -i).
expect_out() {
  if grep -qEi -- "$2" "$out"; then pass "$1: output mentions /$2/"; else
    fail "$1: output lacks /$2/; output:"
    sed 's/^/      /' "$out" | tail -20
  fi
}
png_bit_depth() { od -An -tu1 -j24 -N1 "$1" | tr -d ' '; }   # IHDR bit depth byte
view_ids() { python3 -c 'import json,sys; print("\n".join(str(c["id"]) for c in json.load(open(sys.argv[1]))["cameras"]))' "$1"; }

t0=$SECONDS
city=$DIR/city

# --- demo --generate-only: a small city (fast), same files as the default one
run demo demo --out "$DIR" --generate-only --buildings 8 --photos 12 --views 3
expect_rc demo 0
for f in scene.json views.json cameras.json buildings.geojson dtm.tif; do
  check "demo wrote city/$f" test -s "$city/$f"
done
mapfile -t ids < <(view_ids "$city/views.json")
check "views.json has views" test "${#ids[@]}" -gt 0

# --- info
run info info "$city/scene.json"
expect_rc info 0
expect_out info "photos +12"
expect_out info "buildings +[1-9][0-9]* triangles"
expect_out info "terrain +[1-9][0-9]* vertices"
expect_out info "MAX_ARRAY_TEXTURE_LAYERS [0-9]+"
expect_out info "MAX_TEXTURE_SIZE [0-9]+"
expect_out info "tiles +terrain meshed whole; buildings [1-9][0-9]* of [1-9][0-9]* loaded"
expect_out info "note: buildings: .*indexed in memory"
expect_out info "memory +geometry: [1-9][0-9]* triangles, CPU [0-9.]+ MiB, GPU [0-9.]+ MiB"
expect_out info "memory +images: [1-9][0-9]* slots of [0-9]+x[0-9]+ RGBA, GPU [0-9.]+ MiB"
expect_out info "memory +depth maps: [1-9][0-9]* of 1024x1024 float, GPU [0-9.]+ MiB"

# --- render with coverage and the count debug output
r=$DIR/r
run render render "$city/scene.json" --views "$city/views.json" --out "$r" --coverage --debug count --k 4
expect_rc render 0
for id in "${ids[@]}"; do
  for suffix in .png .coverage.png .count.png .count-preview.png; do
    check "render wrote $id$suffix" test -s "$r/$id$suffix"
  done
  check "$id.count.png is a 16-bit PNG" test "$(png_bit_depth "$r/$id.count.png")" = 16
  check "$id.png is an 8-bit PNG" test "$(png_bit_depth "$r/$id.png")" = 8
done

# --- --size: same aspect works; another aspect is cropped or padded; too large names one that fits
w=$(python3 -c 'import json,sys; c=json.load(open(sys.argv[1]))["cameras"][0]; print(c["width"], c["height"])' "$city/views.json")
read -r vw vh <<<"$w"
if ((vw * 120 == vh * 160)); then
  run size render "$city/scene.json" --views "$city/views.json" --out "$DIR/r160" --size 160x120 --k 4
  expect_rc size-160x120 0
  check "--size 160x120 wrote ${ids[0]}.png" test -s "$DIR/r160/${ids[0]}.png"
  check "--size 160x120 output is 160 wide" \
    test "$(od -An -tu1 -j16 -N4 "$DIR/r160/${ids[0]}.png" | awk '{print $1*16777216+$2*65536+$3*256+$4}')" = 160
else
  fail "views are ${vw}x${vh}, not 4:3: cannot check --size 160x120"
fi
png_size() { od -An -tu1 -j16 -N8 "$1" | awk '{print ($1*16777216+$2*65536+$3*256+$4) "x" ($5*16777216+$6*65536+$7*256+$8)}'; }
# Another aspect ratio is cropped (default) or padded, not refused.
run aspect render "$city/scene.json" --views "$city/views.json" --out "$DIR/r100" --size 100x100 --k 4
expect_rc size-100x100 0
check "--size 100x100 (crop) wrote a 100x100 PNG" test "$(png_size "$DIR/r100/${ids[0]}.png")" = 100x100
run aspect-pad render "$city/scene.json" --views "$city/views.json" --out "$DIR/r100p" --size 100x100 --fit pad --k 4
expect_rc size-100x100-pad 0
check "--fit pad wrote a 100x100 PNG" test "$(png_size "$DIR/r100p/${ids[0]}.png")" = 100x100
check "--fit pad shows more than --fit crop (another picture)" \
  bash -c "! cmp -s '$DIR/r100/${ids[0]}.png' '$DIR/r100p/${ids[0]}.png'"
# A size too large is refused, naming the nearest that fits.
run toolarge render "$city/scene.json" --views "$city/views.json" --out "$DIR/rtoolarge" --size 40000x30000 --k 4
expect_rc huge-size fail
expect_out huge-size "nearest size that fits.*--size [0-9]+x[0-9]+"

# --- viewpoints without a cameras file: --camera, --eye/--look-at, --step-back
photo=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["cameras"][0]["id"])' "$city/cameras.json")
run camera render "$city/scene.json" --camera "$photo" --out "$DIR/rcam" --size 160x120 --k 4
expect_rc render-camera 0
check "--camera $photo wrote $photo.png (160x120)" test "$(png_size "$DIR/rcam/$photo.png")" = 160x120
run camera-back render "$city/scene.json" --camera "$photo" --step-back 20 --out "$DIR/rback" --size 160x120 --k 4
expect_rc render-step-back 0
check "--step-back gives another picture than the photograph's view" \
  bash -c "! cmp -s '$DIR/rcam/$photo.png' '$DIR/rback/$photo.png'"
run camera-unknown render "$city/scene.json" --camera no-such-id --out "$DIR/rnone" --k 4
expect_rc camera-unknown 2
expect_out camera-unknown "--camera no-such-id: no photograph .* has this id \(ids: "
centre=$(python3 -c 'import json,sys
c=json.load(open(sys.argv[1]))["cameras"][0]["center"]; print(",".join(str(v) for v in c))' "$city/cameras.json")
read -r cx cy cz < <(tr , ' ' <<<"$centre")
run eye render "$city/scene.json" --eye "$cx,$cy,$cz" --look-at "$(python3 -c "print($cx+50, $cy+20, $cz-5, sep=',')")" \
  --fov 70 --out "$DIR/reye" --size 128x96 --k 4
expect_rc render-eye 0
check "--eye wrote eye.png (128x96)" test "$(png_size "$DIR/reye/eye.png")" = 128x96
run eye-half render "$city/scene.json" --eye "$cx,$cy,$cz" --out "$DIR/reye2" --k 4
expect_rc eye-without-look-at 2
expect_out eye-without-look-at "--eye needs --look-at"
run render-nothing render "$city/scene.json" --out "$DIR/rnothing"
expect_rc render-nothing 2
expect_out render-nothing "--views FILE, --camera ID or --eye"
run fly-camera fly "$city/scene.json" --camera "$photo" --step-back 10 --fps 2 --out "$DIR/fcam" --size 96x72 --k 4
expect_rc fly-camera 0
check "fly --camera --step-back wrote frames (hold + step back at 2 fps)" test -s "$DIR/fcam/f00003.png"
run flicker eval "$city/scene.json" --flicker "$DIR/fcam"
expect_rc flicker 0
expect_out flicker "flicker +[0-9.]+ luma levels .* consecutive frame pairs"
mkdir -p "$DIR/noframes"
run flicker-none eval "$city/scene.json" --flicker "$DIR/noframes"
expect_rc "eval --flicker without frames" fail
expect_out "eval --flicker without frames" "0 frame\\(s\\) f\\*.png"

# --- eval: table with a mean row, JSON with the methods
run eval eval "$city/scene.json" --views "$city/views.json" --truth "$city/truth" --method blend,nearest \
  --json "$DIR/e.json" --k 4
expect_rc eval 0
expect_out eval "mean"
expect_out eval "nearest"
expect_out eval "mean +blend +[0-9]"
check "eval wrote e.json with \"methods\"" grep -q '"methods"' "$DIR/e.json"
run eval-border eval "$city/scene.json" --views "$city/views.json" --truth "$city/truth" --k 4 --border-seams \
  --json "$DIR/eb.json"
expect_rc eval-border 0
expect_out eval-border "PSNR dB +SSIM +coverage +scored +seam"
check "eval --border-seams saved a seam per view" grep -q '"seam": -\?[0-9]' "$DIR/eb.json"

# One view whose truth cannot be read (a symlink loop) is that view's alone: the others are scored,
# the status says a view asked for was not produced (1).
cp -r "$city/truth" "$DIR/truth-loop"
rm -f "$DIR/truth-loop/${ids[0]}".*
ln -sf "${ids[0]}.jpg" "$DIR/truth-loop/${ids[0]}.png"; ln -sf "${ids[0]}.png" "$DIR/truth-loop/${ids[0]}.jpg"
run_capped eval-loop "$HV" eval "$city/scene.json" --views "$city/views.json" --truth "$DIR/truth-loop" --k 4
expect_rc "eval with one truth a symlink loop" 1
expect_out "eval with one truth a symlink loop" "${ids[0]}.*not scored"
expect_out "eval with one truth a symlink loop" "mean +blend +[0-9]"

# A view id that is a path ("../stolen") names its truth as `render` names its output (a safe
# stem inside --truth), never a file outside the folder.
mkdir -p "$DIR/truth-esc"
cp "$city/truth/"* "$DIR/truth-esc/"
rm -f "$DIR/truth-esc/${ids[0]}".*
cp "$city/truth/${ids[0]}.png" "$DIR/stolen.png" 2>/dev/null || cp "$city/truth/${ids[0]}.jpg" "$DIR/stolen.png"
python3 - "$city/views.json" "$DIR/views-esc.json" "${ids[0]}" <<'PY'
import json, sys
v = json.load(open(sys.argv[1]))
for c in v["cameras"]:
    if str(c["id"]) == sys.argv[3]:
        c["id"] = "../stolen"
json.dump(v, open(sys.argv[2], "w"))
PY
run_capped eval-esc "$HV" eval "$city/scene.json" --views "$DIR/views-esc.json" --truth "$DIR/truth-esc" --k 4
expect_rc "eval with a view id ../stolen" 1
expect_out "eval with a view id ../stolen" "no truth image [^ ]*stolen-[0-9a-f]{8}"
expect_out "eval with a view id ../stolen" "mean +blend +[0-9]"

# --- eval --seams (measured on real panoramas in src/hv/eval/paris_seams_test.cpp): a panorama id
# that no photograph ends with is an error naming it
run seams-none eval "$city/scene.json" --seams no-such-pano
expect_rc "eval --seams with an unknown panorama" fail
expect_out "eval --seams with an unknown panorama" "no-such-pano"
run seams-views eval "$city/scene.json" --seams p1 --leave-one-out
expect_rc "eval --seams with --leave-one-out" fail
expect_out "eval --seams with --leave-one-out" "seams"

# --- broken inputs: clean errors, never a crash
printf 'this is { not JSON' >"$DIR/not-json.json"
run bad-scene info "$DIR/not-json.json"
expect_rc "info on a scene.json that is not JSON" fail
expect_out "info on a scene.json that is not JSON" "not-json.json.*(JSON|json)"
run bad-scene-render render "$DIR/not-json.json" --views "$city/views.json" --out "$DIR/rbad"
expect_rc "render of a scene.json that is not JSON" fail
expect_out "render of a scene.json that is not JSON" "not-json.json"

run missing-views render "$city/scene.json" --views "$DIR/no-such-views.json" --out "$DIR/rmissing"
expect_rc "render with a missing views file" fail
expect_out "render with a missing views file" "no-such-views.json"

run missing-scene info "$DIR/no-such-scene.json"
expect_rc "info on a missing scene.json" fail
expect_out "info on a missing scene.json" "no-such-scene.json"

# One photograph with a non-orthonormal rotation among good ones: it is reported (file, camera,
# field) and left out, the scene still renders every view, the exit status says "produced, with
# items left out" (3, docs/reliability.md).
python3 - "$city" <<'PY'
import json, sys
city = sys.argv[1]
cams = json.load(open(f"{city}/cameras.json"))
cams["cameras"][0]["rotation"] = [1, 0.3, 0, 0, 1, 0, 0, 0, 1]
json.dump(cams, open(f"{city}/cameras-badrot.json", "w"))
scene = json.load(open(f"{city}/scene.json"))
scene["cameras"]["path"] = "cameras-badrot.json"
json.dump(scene, open(f"{city}/scene-badrot.json", "w"))
views = json.load(open(f"{city}/views.json"))
views["cameras"][0]["rotation"] = [2, 0, 0, 0, 1, 0, 0, 0, 1]
json.dump(views, open(f"{city}/views-badrot.json", "w"))
PY
read -r badphoto badview < <(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["cameras"][0]["id"], json.load(open(sys.argv[2]))["cameras"][0]["id"])' "$city/cameras.json" "$city/views.json")

run badrot-photo render "$city/scene-badrot.json" --views "$city/views.json" --out "$DIR/rbadphoto" --k 4 --size 160x120
expect_rc "render with one bad photo camera" 3
expect_out "render with one bad photo camera" "cameras-badrot.json.*$badphoto.*rotation"
for id in "${ids[@]}"; do
  check "bad photo camera: view $id still written" test -s "$DIR/rbadphoto/$id.png"
done

run badrot-view render "$city/scene.json" --views "$city/views-badrot.json" --out "$DIR/rbadview" --k 4 --size 160x120
expect_rc "render with one bad view camera" 3
expect_out "render with one bad view camera" "views-badrot.json.*$badview.*rotation"
check "bad view camera: not rendered" test ! -e "$DIR/rbadview/$badview.png"
for id in "${ids[@]:1}"; do
  check "bad view camera: good view $id still written" test -s "$DIR/rbadview/$id.png"
done

# Layered projective texture maps (`histoview layers export`, docs/layers.md): an OpenRaster file,
# mimetype first and stored, layers named L<k> top first, the guide hidden; an unknown photograph
# and a size of another aspect ratio are refused, named.
layer_id=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["cameras"][0]["id"])' "$city/cameras.json")
run layers layers export "$city/scene.json" --image "$layer_id" "$DIR/layers.ora" --size 160x120
expect_rc "layers export" 0
expect_out "layers export" "[0-9]+ visibility layers, [0-9]+ image layers"
# The cycles met and how they were split (faces, triangles, pixel level) are counted.
expect_out "layers export" "[0-9]+ cycles \([0-9]+ objects split into faces, [0-9]+ faces into triangles, [0-9]+ broken at pixel level\)"
check "layers export: an OpenRaster file" python3 - "$DIR/layers.ora" <<'PY'
import re, sys, zipfile, xml.etree.ElementTree as ET
z = zipfile.ZipFile(sys.argv[1])
first = z.infolist()[0]
assert first.filename == "mimetype" and first.compress_type == zipfile.ZIP_STORED, first
assert z.read("mimetype") == b"image/openraster"
image = ET.fromstring(z.read("stack.xml"))
assert (image.get("w"), image.get("h")) == ("160", "120"), image.attrib
layers = image.find("stack").findall("layer")
assert layers[0].get("visibility") == "hidden", layers[0].attrib
ks = [int(m.group(1)) for l in layers if (m := re.match(r"L([0-9]+) ", l.get("name")))]
assert ks and ks[0] == 1 and ks == sorted(ks), ks
for l in layers:
    png = z.read(l.get("src"))
    assert png[:8] == b"\x89PNG\r\n\x1a\n", l.get("src")
for name in ("mergedimage.png", "Thumbnails/thumbnail.png"):
    z.getinfo(name)
PY
# The peeling the command used is printed (auto: the CPU on a software renderer such as llvmpipe);
# the GPU pass and the CPU reference give the same stack.
expect_out "layers export" "peeling: (GPU|CPU) "
run layers-gpu layers export "$city/scene.json" --image "$layer_id" "$DIR/layers-gpu.ora" --size 160x120 --peeling gpu
expect_rc "layers export --peeling gpu" 0
expect_out "layers export --peeling gpu" "peeling: GPU "
run layers-cpu layers export "$city/scene.json" --image "$layer_id" "$DIR/layers-cpu.ora" --size 160x120 --peeling cpu
expect_rc "layers export --peeling cpu" 0
expect_out "layers export --peeling cpu" "peeling: CPU "
check "layers export: the same stack whichever peels" python3 - "$DIR/layers-gpu.ora" "$DIR/layers-cpu.ora" <<'PY'
import sys, zipfile
a, b = (zipfile.ZipFile(f).read("stack.xml") for f in sys.argv[1:3])
assert a == b, (a, b)
PY
run layers-unknown layers export "$city/scene.json" --image no-such-photo "$DIR/layers-x.ora"
expect_rc "layers export: unknown photograph" 2
expect_out "layers export: unknown photograph" "no photograph with id 'no-such-photo'"
run layers-size layers export "$city/scene.json" --image "$layer_id" "$DIR/layers-x.ora" --size 160x160
expect_rc "layers export: another aspect ratio" 1
expect_out "layers export: another aspect ratio" "aspect ratio"
# The exported file named by scene.json's "layers" textures the photograph in render; a file that is
# not OpenRaster is reported, naming it, and the photograph renders as itself.
python3 - "$city/scene.json" "$city/scene-layers.json" "$layer_id" "$DIR/layers.ora" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["layers"] = {sys.argv[3]: sys.argv[4]}
json.dump(scene, open(sys.argv[2], "w"))
PY
HV_LOG=info run layers-render render "$city/scene-layers.json" --camera "$layer_id" --out "$DIR/rlayers" --size 160x120
expect_rc "render with edited layers" 0
expect_out "render with edited layers" "layers: photograph '$layer_id' textured with [0-9]+ edited sub-image"
check "render with edited layers: the view written" test -s "$DIR/rlayers/$layer_id.png"
echo "not a zip" > "$DIR/layers-bad.ora"
python3 - "$city/scene.json" "$city/scene-layers-bad.json" "$layer_id" "$DIR/layers-bad.ora" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["layers"] = {sys.argv[3]: sys.argv[4]}
json.dump(scene, open(sys.argv[2], "w"))
PY
run layers-bad render "$city/scene-layers-bad.json" --camera "$layer_id" --out "$DIR/rlayersbad" --size 160x120
expect_rc "render with a broken layers file" 3
expect_out "render with a broken layers file" "layers-bad.ora.*layers of photograph '$layer_id' left out"
check "broken layers file: the view still written" test -s "$DIR/rlayersbad/$layer_id.png"

# Colour corrections (`histoview harmonize`); a bad entry is reported (file, entry, field) and the
# rest renders with the others' corrections.
run harmonize harmonize "$city/scene.json" -o "$city/corrections.json" --samples 1500
expect_rc harmonize 0
expect_out harmonize "[0-9]+ pairs; colour difference"
check "harmonize wrote the corrections" grep -q '"model": "gain-offset"' "$city/corrections.json"
python3 - "$city" "$badphoto" <<'PY'
import json, sys
city, bad = sys.argv[1], sys.argv[2]
c = json.load(open(f"{city}/corrections.json"))
for e in c["corrections"]:
    if e["id"] == bad: e["gain"] = [1, "x", 1]
json.dump(c, open(f"{city}/corrections-bad.json", "w"))
scene = json.load(open(f"{city}/scene.json"))
scene["colour"] = "corrections-bad.json"
json.dump(scene, open(f"{city}/scene-badcolour.json", "w"))
PY
run badcolour render "$city/scene-badcolour.json" --views "$city/views.json" --out "$DIR/rbadcolour" --k 4 --size 160x120
expect_rc "render with one bad colour correction" 3
expect_out "render with one bad colour correction" "corrections-bad.json: corrections\\[[0-9]+\\] \\('$badphoto'\\): gain"
for id in "${ids[@]}"; do
  check "bad colour correction: view $id still written" test -s "$DIR/rbadcolour/$id.png"
done

run bad-size render "$city/scene.json" --views "$city/views.json" --out "$DIR/rbadsize" --size 160by120
expect_rc "render --size 160by120" fail

# --- cameras convert: native in, native out (same cameras); a MicMac block georeferenced into Lambert-93
run convert-native cameras convert "$city/scene.json" -o "$DIR/conv/cameras.json"
expect_rc "cameras convert (native)" 0
check "cameras convert (native): same cameras to 1e-9" python3 - "$city/cameras.json" "$DIR/conv/cameras.json" <<'PY'
import json, sys
a = {c["id"]: c for c in json.load(open(sys.argv[1]))["cameras"]}
b = {c["id"]: c for c in json.load(open(sys.argv[2]))["cameras"]}
assert a.keys() == b.keys()
for k in a:
    for f in ("center", "rotation", "focal", "principal"):
        assert all(abs(x - y) <= 1e-9 * max(1.0, abs(x)) for x, y in zip(a[k][f], b[k][f])), (k, f)
PY
mm=$DIR/micmac
mkdir -p "$mm/Ori-T" "$mm/img"
cp "$city/$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["cameras"][0]["image"])' "$city/cameras.json")" "$mm/img/a.jpg"
cat >"$mm/Ori-T/AutoCal.xml" <<'XML'
<ExportAPERO><CalibrationInternConique><KnownConv>eConvApero_DistM2C</KnownConv><PP>320 240</PP><F>1000</F>
<SzIm>640 480</SzIm><CalibDistortion><ModRad><CDist>320 240</CDist></ModRad></CalibDistortion></CalibrationInternConique></ExportAPERO>
XML
cat >"$mm/Ori-T/Orientation-a.jpg.xml" <<'XML'
<ExportAPERO><OrientationConique><FileInterne>Ori-T/AutoCal.xml</FileInterne><Externe>
<Centre>4201000 177000 4779000</Centre><ParamRotation><CodageMatr><L1>1 0 0</L1><L2>0 1 0</L2><L3>0 0 1</L3></CodageMatr></ParamRotation>
</Externe></OrientationConique></ExportAPERO>
XML
cat >"$mm/Ori-T/Orientation-missing.jpg.xml" <<'XML'
<ExportAPERO><OrientationConique><FileInterne>Ori-T/AutoCal.xml</FileInterne><Externe>
<Centre>4201000 177000 4779000</Centre><ParamRotation><CodageMatr><L1>1 0 0</L1><L2>0 1 0</L2><L3>0 0 1</L3></CodageMatr></ParamRotation>
</Externe></OrientationConique></ExportAPERO>
XML
echo '{"crs": "EPSG:2154", "cameras": {"format": "micmac", "orientations": "Ori-T/", "images": "img/"}}' >"$mm/scene.json"
run convert-micmac cameras convert "$mm/scene.json" -o "$mm/out/cameras.json"
expect_rc "cameras convert (micmac, one image missing)" 3
expect_out "cameras convert (micmac, one image missing)" "Orientation-missing.jpg.xml.*missing.jpg.*not found"
expect_out "cameras convert (micmac, one image missing)" "wrote 1 camera"
check "cameras convert (micmac): centre in Lambert-93" python3 - "$mm/out/cameras.json" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))["cameras"][0]
x, y, z = c["center"]
assert 100000 < x < 1300000 and 6000000 < y < 7200000, c["center"]
PY
# A photograph whose file name is not UTF-8 (JSON cannot hold it): that camera alone is left out.
mm2=$DIR/micmac-utf8
mkdir -p "$mm2"
cp -r "$mm/Ori-T" "$mm/img" "$mm/scene.json" "$mm2/"
rm "$mm2/Ori-T/Orientation-missing.jpg.xml"
cp "$mm/img/a.jpg" "$mm2/img/"$'\xff'".jpg"
cp "$mm/Ori-T/Orientation-a.jpg.xml" "$mm2/Ori-T/Orientation-"$'\xff'".jpg.xml"
run convert-utf8 cameras convert "$mm2/scene.json" -o "$mm2/out/cameras.json"
expect_rc "cameras convert with a file name that is not UTF-8" 3
expect_out "cameras convert with a file name that is not UTF-8" "not valid UTF-8.*left out"
expect_out "cameras convert with a file name that is not UTF-8" "wrote 1 camera"
run web-utf8 web-export "$mm2/scene.json" "$mm2/web" --page "$DIR/none" --wasm "$DIR/none"
expect_rc "web-export with a file name that is not UTF-8" 3
expect_out "web-export with a file name that is not UTF-8" "not valid UTF-8"
check "web-export with a file name that is not UTF-8: the other photograph published" test "$(ls "$mm2/web/images" | wc -l)" = 1
run info-micmac info "$mm/scene.json"
expect_out "info (micmac)" "Lambert-93 \\(EPSG:2154\\)"
expect_out "info (micmac)" "cameras from .*EPSG:4978"

# --- messages that help: a warning once per run, naming only real options
HV_LOG=warn run kslots render "$city/scene.json" --views "$city/views.json" --out "$DIR/rkslots" --k 4 --size 160x120 \
  --max-slices 2 --selection global
expect_rc "render --max-slices 2" 0
check "K capped by the slots: said once for ${#ids[@]} views" test "$(grep -c 'exceeds the image slots' "$out")" = 1
expect_out "render --max-slices 2" "bounded by --max-slices 2\)"
HV_LOG=warn run kphotos render "$city/scene.json" --views "$city/views.json" --out "$DIR/rkphotos" --k 20 --size 160x120 \
  --selection global
expect_rc "render --k 20 on 12 photographs" 0
check "K above the photographs' count is no warning" bash -c "! grep -q 'exceeds the image slots' '$out'"
python3 - "$city" <<'PY'
import json, sys
city = sys.argv[1]
cams = json.load(open(f"{city}/cameras.json"))
for i, c in enumerate(cams["cameras"]):
    c["date"] = f"{1890 + i}-06-01"
json.dump(cams, open(f"{city}/cameras-dated.json", "w"))
scene = json.load(open(f"{city}/scene.json"))
scene["cameras"]["path"] = "cameras-dated.json"
json.dump(scene, open(f"{city}/scene-dated.json", "w"))
scene = json.load(open(f"{city}/scene.json"))
scene["terain"] = scene.pop("terrain")
json.dump(scene, open(f"{city}/scene-terain.json", "w"))
PY
run from1990 render "$city/scene-dated.json" --views "$city/views.json" --out "$DIR/rfrom" --size 160x120 --from 1990
expect_rc "render --from 1990" 0
expect_out "render --from 1990" "selects 0 of 12 photographs .*dates span 1890-06-01 \.\. 1901-06-01"
run terain info "$city/scene-terain.json"
expect_rc "info: scene.json with \"terain\"" 2
expect_out "info: scene.json with \"terain\"" "unknown key 'terain' \(did you mean 'terrain'\?\)"
# Every option a message names (a string literal of src/ or apps/ with --name) is one that some
# --help lists.
helps=$DIR/helps.txt
"$HV" --help >"$helps" 2>&1
subs() { sed -n '/^Subcommands:/,/^$/p' | awk 'NR > 1 && NF {print $1}'; }
for sub in $("$HV" --help | subs); do
  "$HV" "$sub" --help >>"$helps" 2>&1
  for subsub in $("$HV" "$sub" --help | subs); do "$HV" "$sub" "$subsub" --help >>"$helps" 2>&1; done
done
check "every option named in the sources' messages is listed by some --help" \
  python3 - "$(dirname "$0")/.." "$helps" <<'PY'
import os, re, sys
root, helps = sys.argv[1], open(sys.argv[2]).read()
literal = re.compile(r'R"\((.*?)\)"|"((?:[^"\\\n]|\\.)*)"', re.S)
option = re.compile(r'(?<![\w-])--([a-z][a-z0-9]*(?:-[a-z0-9]+)*)(?![\w-])')
listed = set(re.findall(r'(?<![\w-])--([a-z](?:[a-z0-9-]*[a-z0-9])?)', helps))
missing = []
for top in ("src", "apps"):
    for d, _, files in os.walk(os.path.join(root, top)):
        for f in files:
            if not f.endswith((".cpp", ".h")) or re.search(r"_(gl)?test\.cpp$", f):
                continue
            text = re.sub(r"(?m)^\s*//.*$", "", open(os.path.join(d, f), errors="replace").read())
            for m in literal.finditer(text):
                for name in option.findall(m.group(1) if m.group(1) is not None else m.group(2)):
                    if name not in listed:
                        missing.append(f"--{name} ({os.path.relpath(os.path.join(d, f), root)})")
assert listed and not missing, "named in messages, listed by no --help: " + ", ".join(sorted(set(missing)))
PY

# --- a ground plane instead of a DTM, and the hint for a scene with cameras but no geometry
python3 - "$city" <<'PY'
import json, sys
city = sys.argv[1]
scene = json.load(open(f"{city}/scene.json"))
json.dump({"crs": scene["crs"], "terrain": {"height": 35}, "cameras": scene["cameras"]},
          open(f"{city}/scene-ground.json", "w"))
json.dump({"crs": scene["crs"], "cameras": scene["cameras"]}, open(f"{city}/scene-nogeometry.json", "w"))
PY
run ground info "$city/scene-ground.json"
expect_rc "info: terrain.height" 0
expect_out "info: terrain.height" "terrain +289 vertices, 512 triangles"
expect_out "info: terrain.height" "a ground plane at height 35"
expect_out "info: terrain.height" "hint .*projected onto the ground plane.*footprints"
run nogeometry info "$city/scene-nogeometry.json"
expect_rc "info: cameras alone" 0
expect_out "info: cameras alone" "hint .*footprints.*\"terrain\": \{\"height\": H\} gives a ground plane"

# --- init: a folder of data to a scene.json (here the demo city's files), refusing to overwrite
own=$DIR/own
mkdir -p "$own"
cp -r "$city/images" "$city/masks" "$city/cameras.json" "$city/views.json" "$city/dtm.tif" "$city/buildings.geojson" \
  "$city/points.las" "$own/"
run init init "$own"
expect_rc "init" 0
expect_out "init" "cameras +cameras.json \(histoview's own format, 12 cameras\)"
expect_out "init" "buildings +buildings.geojson \(8 footprints, height from the 'height' attribute"
expect_out "init" "crs +EPSG:2154|crs +.*Lambert"
check "init wrote the scene of the demo's own scene.json" python3 - "$own/scene.json" "$city/scene.json" <<'PY'
import json, sys
got, want = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
for key in ("terrain", "points", "cameras"):
    assert got[key] == want[key], (key, got.get(key), want[key])
assert got["buildings"]["path"] == want["buildings"]["path"] and got["buildings"]["height"] == "height", got
PY
run init-info info "$own/scene.json"
expect_rc "info on the scene init wrote" 0
expect_out "info on the scene init wrote" "photos +12"
expect_out "info on the scene init wrote" "buildings +[1-9][0-9]* triangles"
run init-again init "$own"
expect_rc "init over an existing scene.json" 1
expect_out "init over an existing scene.json" "exists; --force overwrites it"
run init-force init "$own" --force
expect_rc "init --force" 0
# The real data, when there: a scene written elsewhere (the data folders are read-only) loads.
data=${HISTOVIEW_DATA:-$(dirname "$0")/../../shared/data}
for set in delft paris-historical-micmac sceaux paris-stereopolis autzen; do
  [[ -d $data/$set ]] || continue
  run "init-$set" init "$data/$set" -o "$DIR/init-$set/scene.json"
  expect_rc "init $set" 0
  run "init-$set-info" info "$DIR/init-$set/scene.json"
  expect_rc "info on the scene init wrote for $set" 0
done

# --- settings: the README's table of render settings is the command's output (docs cannot
# drift from the schema), and a render setting's bad value is refused naming it
run settings settings --markdown
expect_rc "settings --markdown" 0
check "README.md's settings table is the output of histoview settings --markdown" \
  python3 - "$out" "$(dirname "$0")/../README.md" <<'PY'
import sys
table = open(sys.argv[1]).read()
readme = open(sys.argv[2]).read()
begin, end = "<!-- settings:begin -->\n", "<!-- settings:end -->"
assert readme[readme.index(begin) + len(begin):readme.index(end)] == table
PY
run settings-json settings --json
expect_rc "settings --json" 0
expect_out "settings --json" '"name": "depth-size"'
run bad-k render "$city/scene.json" --views "$city/views.json" --out "$DIR/rbadk" --k 0
expect_rc "render --k 0" fail
expect_out "render --k 0" "--k.*a whole number >= 1"
check "render --k 0: no 309-digit range" bash -c "! grep -qE '[0-9]{30}' '$out'"

# --- exit statuses (docs/reliability.md): --strict stops before rendering when an item is left out
run strict render "$city/scene-badrot.json" --views "$city/views.json" --out "$DIR/rstrict" --k 4 --size 160x120 --strict
expect_rc "render --strict with one bad photo camera" 1
expect_out "render --strict with one bad photo camera" "strict.*left out"
check "render --strict: nothing written" test ! -e "$DIR/rstrict/${ids[0]}.png"

# Option values that used to mean something else, or print a 309-digit range, are refused by name.
for sigma in 0 -1 nan inf 1e200; do
  run "sigma$sigma" render "$city/scene.json" --views "$city/views.json" --out "$DIR/rsigma" --sigma="$sigma"
  expect_rc "render --sigma $sigma" fail
  expect_out "render --sigma $sigma" "--sigma: expected a number"
done
check "--sigma refused: nothing written" test ! -e "$DIR/rsigma"
run exclude render "$city/scene.json" --views "$city/views.json" --out "$DIR/rexcl" --k 4 --size 160x120 \
  --exclude no-such-photo
expect_rc "render --exclude with an unknown id" 0
expect_out "render --exclude with an unknown id" "exclude.*no-such-photo"
# Views too large: refused naming the size and the limit, the other views still rendered.
python3 - "$city" <<'PY'
import json, sys
city = sys.argv[1]
views = json.load(open(f"{city}/views.json"))
big = dict(views["cameras"][0]); big["id"] = "huge"
for k in ("width", "height"): big[k] = big[k] * 100
big["focal"] = [f * 100 for f in big["focal"]]; big["principal"] = [p * 100 for p in big["principal"]]
views["cameras"].append(big)
json.dump(views, open(f"{city}/views-huge.json", "w"))
PY
run huge render "$city/scene.json" --views "$city/views-huge.json" --out "$DIR/rhuge" --k 4
expect_rc "render a view beyond MAX_TEXTURE_SIZE" 1
expect_out "render a view beyond MAX_TEXTURE_SIZE" "huge.*MAX_TEXTURE_SIZE"
check "render a huge view: the others still written" test -s "$DIR/rhuge/${ids[0]}.png"

# An empty cameras file is said as such.
echo '{"cameras": []}' >"$city/cameras-empty.json"
python3 - "$city" <<'PY'
import json, sys
city = sys.argv[1]
scene = json.load(open(f"{city}/scene.json"))
scene["cameras"]["path"] = "cameras-empty.json"
json.dump(scene, open(f"{city}/scene-nocams.json", "w"))
PY
run_capped nocams "$HV" render "$city/scene-nocams.json" --views "$city/views.json" --out "$DIR/rnocams" --k 4 --size 160x120
expect_out "render with an empty cameras file" "no photograph loaded"

# --- output paths are ours: hostile view ids never write outside --out; duplicates do not overwrite
escape=/tmp/hv-cli-escape-$$
python3 - "$city" "$escape" <<'PY'
import json, sys
city, escape = sys.argv[1], sys.argv[2]
views = json.load(open(f"{city}/views.json"))
base = views["cameras"][0]
hostile = ["../../escaped", escape, "a/b", ".hidden", "v" * 300, "dup", "dup", "DUP"]
views["cameras"] = [dict(base, id=i) for i in hostile]
json.dump(views, open(f"{city}/views-hostile.json", "w"))
PY
sandbox=$DIR/sandbox/one/two
mkdir -p "$sandbox"
run_capped hostile "$HV" render "$city/scene.json" --views "$city/views-hostile.json" --out "$sandbox/out" --k 4 --size 160x120
# The second "dup" is left out by the cameras reader (a duplicate id: exit 3, named); "DUP" is
# another id whose file name collides with "dup"'s on a case-insensitive file system: a suffix.
expect_rc "render with hostile view ids" 3
expect_out "render with hostile view ids" "camera 'dup': duplicate id"
expect_out "render with hostile view ids" "note: view id '../../escaped' written as"
check "hostile ids: 7 views, 7 files, all inside --out" test "$(find "$sandbox/out" -name '*.png' | wc -l)" = 7
check "hostile ids: nothing outside --out" test "$(find "$DIR/sandbox" -type f | grep -vc "^$sandbox/out/")" = 0
check "hostile ids: no absolute path written" test ! -e "$escape.png"
check "hostile ids: no hidden file" test "$(find "$sandbox/out" -name '.*' | wc -l)" = 0
check "hostile ids: names of at most 255 bytes" bash -c "find '$sandbox/out' -type f -printf '%f\n' | LC_ALL=C awk 'length > 255 { bad = 1 } END { exit bad }'"

# --- web-export publishes only what it decoded: a mask naming a text file, a PNG bomb, are left out
secret=$DIR/secret.txt
echo 'root:x:0:0:root:/root:/bin/bash' >"$secret"
python3 - "$city" "$secret" <<'PY'
import json, struct, sys, zlib
city, secret = sys.argv[1], sys.argv[2]
# An 8000x8000 grey PNG of zeros: ~60 KB on disk, ~1 GiB for the decoder.
w = h = 8000
def chunk(t, d): return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
z = zlib.compressobj(9)
row = b"\0" * (w + 1)
idat = b"".join(z.compress(row) for _ in range(h)) + z.flush()
with open(f"{city}/bomb.png", "wb") as f:
    f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0)) + chunk(b"IDAT", idat) + chunk(b"IEND", b""))
cams = json.load(open(f"{city}/cameras.json"))
cams["cameras"][0]["mask"] = secret
cams["cameras"][1]["image"] = "bomb.png"
cams["cameras"][1]["width"], cams["cameras"][1]["height"] = w, h
cams["cameras"][1]["focal"] = [w, w]; cams["cameras"][1]["principal"] = [w / 2, h / 2]
json.dump(cams, open(f"{city}/cameras-hostile.json", "w"))
scene = json.load(open(f"{city}/scene.json"))
scene["cameras"]["path"] = "cameras-hostile.json"
json.dump(scene, open(f"{city}/scene-hostile.json", "w"))
PY
read -r cam0 cam1 < <(python3 -c 'import json,sys; c=json.load(open(sys.argv[1]))["cameras"]; print(c[0]["id"], c[1]["id"])' "$city/cameras.json")
web=$DIR/sandbox-web/out
mkdir -p "$DIR/sandbox-web"
# Within a 3 GiB address space (the bomb alone would ask the decoder for about 1 GiB, 30000 x 30000 for 3.6).
(ulimit -v 3145728; exec "$HV" web-export "$city/scene-hostile.json" "$web" --page "$DIR/none" --wasm "$DIR/none") \
  >"$DIR/web-hostile.out" 2>&1
rc=$?
out=$DIR/web-hostile.out
expect_rc "web-export with a text file as mask and a PNG bomb" 3
expect_out "web-export with a text file as mask and a PNG bomb" "$cam0.*secret.txt.*left out of the export"
expect_out "web-export with a text file as mask and a PNG bomb" "$cam1.*bomb.png.*limit.*left out of the export"
check "web-export: the text file is not published" bash -c "! grep -rq 'root:x:0' '$web'"
check "web-export: the rest is published" test "$(ls "$web/images" | wc -l)" = 10
check "web-export: nothing outside its folder" test "$(find "$DIR/sandbox-web" -type f | grep -vc "^$web/")" = 0

# --- check: 0 for a clean scene, 1 naming what would be left out, 2 when the scene cannot load
run check-clean check "$city/scene.json"
expect_rc "check on the demo city" 0
expect_out "check on the demo city" "12 photograph\\(s\\).*0 item"
run check-deep check "$city/scene.json" --deep --json
expect_rc "check --deep --json on the demo city" 0
check "check --json is JSON with no problems" python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); assert r["problems"] == 0 and r["photographs"] == 12' "$out"
run_capped check-hostile "$HV" check "$city/scene-hostile.json" --deep
expect_rc "check on a scene with a text mask and a PNG bomb" 1
expect_out "check on a scene with a text mask and a PNG bomb" "^masks"
expect_out "check on a scene with a text mask and a PNG bomb" "$cam0.*mask.*secret.txt"
expect_out "check on a scene with a text mask and a PNG bomb" "$cam1.*bomb.png.*limit"
run_capped check-missing "$HV" check "$DIR/not-json.json"
expect_rc "check on a scene.json that is not JSON" 2

# --- outliers: one camera at 1e9 does not black out the views
python3 - "$city" <<'PY'
import json, sys
city = sys.argv[1]
cams = json.load(open(f"{city}/cameras.json"))
far = dict(cams["cameras"][0], id="far-away", center=[1e9, 1e9, 1e9])
cams["cameras"].append(far)
json.dump(cams, open(f"{city}/cameras-far.json", "w"))
scene = json.load(open(f"{city}/scene.json"))
scene["cameras"]["path"] = "cameras-far.json"
scene.pop("origin", None)
json.dump(scene, open(f"{city}/scene-far.json", "w"))
PY
run_capped far "$HV" render "$city/scene-far.json" --views "$city/views.json" --out "$DIR/rfar" --k 4 --size 160x120
expect_rc "render with a camera at 1e9" 0
expect_out "render with a camera at 1e9" "far-away.*left out of the render origin"
mean_png() {  # mean of an 8-bit RGB PNG's samples (no PIL here)
  python3 - "$1" <<'PY'
import struct, sys, zlib
d = open(sys.argv[1], "rb").read(); pos = 8; idat = b""
while pos < len(d):
    n, t = struct.unpack(">I4s", d[pos:pos + 8]); body = d[pos + 8:pos + 8 + n]; pos += 12 + n
    if t == b"IHDR": w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
    if t == b"IDAT": idat += body
raw = zlib.decompress(idat); bpp = 3; stride = w * bpp; prev = bytearray(stride); total = 0; i = 0
for y in range(h):
    f = raw[i]; line = bytearray(raw[i + 1:i + 1 + stride]); i += 1 + stride
    for x in range(stride):
        a = line[x - bpp] if x >= bpp else 0; b = prev[x]; c = prev[x - bpp] if x >= bpp else 0
        p = a + b - c; pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
        pred = [0, a, b, (a + b) // 2, a if pa <= pb and pa <= pc else (b if pb <= pc else c)][f]
        line[x] = (line[x] + pred) & 255
    total += sum(line); prev = line
print(total / (w * h * 3))
PY
}
clean_mean=$(mean_png "$DIR/r160/${ids[0]}.png")
far_mean=$(mean_png "$DIR/rfar/${ids[0]}.png")
check "a camera at 1e9: the view is as bright as without it ($far_mean vs $clean_mean)" \
  python3 -c "import sys; a, b = float(sys.argv[1]), float(sys.argv[2]); assert b > 5 and abs(a - b) < 0.05 * b" "$far_mean" "$clean_mean"

# --- a scene crs PROJ cannot read is named once, not blamed on each source
python3 - "$city" <<'PY'
import json, sys
city = sys.argv[1]
scene = json.load(open(f"{city}/scene.json"))
scene["crs"] = "EPSG:999999"
json.dump(scene, open(f"{city}/scene-badcrs.json", "w"))
scene["crs"] = 12345
json.dump(scene, open(f"{city}/scene-numcrs.json", "w"))
PY
run_capped badcrs "$HV" info "$city/scene-badcrs.json"
expect_rc "info with a scene crs PROJ cannot read" 2
expect_out "info with a scene crs PROJ cannot read" "scene-badcrs.json: crs:"
check "a bad scene crs is named once" test "$(grep -c 'EPSG:999999' "$out")" = 1
run_capped numcrs "$HV" info "$city/scene-numcrs.json"
expect_rc "info with a numeric scene crs" 2
expect_out "info with a numeric scene crs" "crs: expected a CRS string"

# --- info never aborts: a photograph that is a symlink loop is named, the summary still printed
ln -sf loop-b "$city/loop-a"; ln -sf loop-a "$city/loop-b"
python3 - "$city" <<'PY'
import json, sys
city = sys.argv[1]
cams = json.load(open(f"{city}/cameras.json"))
cams["cameras"][2]["image"] = "loop-a"
json.dump(cams, open(f"{city}/cameras-loop.json", "w"))
scene = json.load(open(f"{city}/scene.json"))
scene["cameras"]["path"] = "cameras-loop.json"
json.dump(scene, open(f"{city}/scene-loop.json", "w"))
PY
run_capped info-loop "$HV" info "$city/scene-loop.json"
expect_rc "info with a symlink loop as a photograph" fail
expect_out "info with a symlink loop as a photograph" "loop-a"

# --- a 60,000-photograph collection: one view within 120 s, in a 3 GiB address space (the camera
# index and the spacing are kd-tree queries, the per-frame selection follows the images seen)
python3 - "$city" <<'PY'
import json, random, sys
city = sys.argv[1]
cams = json.load(open(f"{city}/cameras.json"))
base = cams["cameras"]
rng = random.Random(7)
many = []
for i in range(60000):
    c = dict(base[i % len(base)])
    c["id"] = f"m{i:05d}"
    c["center"] = [v + rng.uniform(-3.0, 3.0) for v in c["center"]]
    many.append(c)
cams["cameras"] = many
json.dump(cams, open(f"{city}/cameras-60k.json", "w"))
scene = json.load(open(f"{city}/scene.json"))
scene["cameras"]["path"] = "cameras-60k.json"
json.dump(scene, open(f"{city}/scene-60k.json", "w"))
views = json.load(open(f"{city}/views.json"))
views["cameras"] = views["cameras"][:1]
json.dump(views, open(f"{city}/views-one.json", "w"))
PY
t60=$SECONDS
run_capped many timeout 120 "$HV" render "$city/scene-60k.json" --views "$city/views-one.json" --out "$DIR/r60k" \
  --k 4 --size 160x120
expect_rc "one view of a 60,000-photograph scene within 120 s ($((SECONDS - t60)) s)" 0
check "60,000 photographs: the view was written" test -s "$DIR/r60k/${ids[0]}.png"

# --- pose: a photograph's camera from control points. The demo's camera p0001 is the truth;
# 24 world points in front of it projected through it (pinhole, as the demo's photographs are),
# 0.3 px of noise, 4 of them moved far off (outliers); the first guess 3 m and 10 % of focal away.
python3 - "$city" "$DIR" <<'PY'
import json, math, random, sys
city, out = sys.argv[1], sys.argv[2]
cams = json.load(open(f"{city}/cameras.json"))["cameras"]
c = next(k for k in cams if k["id"] == "p0001")
R = [c["rotation"][0:3], c["rotation"][3:6], c["rotation"][6:9]]   # world -> camera, row-major
random.seed(4)
rows = ["id,u,v,x,y,z"]
while len(rows) < 25:
    u, v, d = random.uniform(0, c["width"]), random.uniform(0, c["height"]), random.uniform(15, 70)
    ray = [(u - c["principal"][0]) / c["focal"][0], (v - c["principal"][1]) / c["focal"][1], 1.0]
    X = [c["center"][i] + d * sum(R[j][i] * ray[j] for j in range(3)) for i in range(3)]   # C + d R^T ray
    n = len(rows)
    if n % 6 == 0:
        u, v = random.uniform(0, c["width"]), random.uniform(0, c["height"])
        name = f"wrong{n}"
    else:
        u, v = u + random.gauss(0, 0.3), v + random.gauss(0, 0.3)
        name = f"pt{n}"
    rows.append(f"{name},{u:.4f},{v:.4f},{X[0]:.4f},{X[1]:.4f},{X[2]:.4f}")
open(f"{out}/gcp.csv", "w").write("\n".join(rows) + "\n")
open(f"{out}/gcp-five.csv", "w").write("\n".join(rows[:6]) + "\n")
open(f"{out}/gcp-bad.csv", "w").write("u,v,x,y,z\n1,2,3,4,5\n10,20,thirty,40,50\n")
g = dict(c)
g["center"] = [c["center"][0] + 3, c["center"][1] - 2, c["center"][2] + 1]
g["focal"] = [c["focal"][0] * 1.1, c["focal"][1] * 1.1]
g.pop("image", None); g.pop("mask", None)
json.dump({"cameras": [g]}, open(f"{out}/pose-start.json", "w"))
json.dump(c, open(f"{out}/pose-truth.json", "w"))
PY
run pose pose "$city/scene.json" --image p0001 --gcp "$DIR/gcp.csv" --start "$DIR/pose-start.json" -o "$DIR/posed.json"
expect_rc "pose from 24 control points, 4 wrong" 0
check "pose: the 4 wrong points are flagged outliers" test "$(grep -c OUTLIER "$out")" -eq 4
expect_out "pose" "centre .*\+/-"
check "pose: centre within 0.1 m, focal within 0.5 % of the truth" python3 - "$DIR/posed.json" "$DIR/pose-truth.json" <<'PY'
import json, math, sys
p = json.load(open(sys.argv[1]))["cameras"][0]
t = json.load(open(sys.argv[2]))
d = math.dist(p["center"], t["center"])
f = abs(p["focal"][0] / t["focal"][0] - 1)
print(f"centre {d:.4f} m off, focal {100 * f:.3f} % off")
sys.exit(0 if d < 0.1 and f < 0.005 else 1)
PY
run pose-render render "$city/scene.json" --views "$DIR/posed.json" --out "$DIR/posed-render" --size 160x120
expect_rc "the posed camera renders" 0
run pose-five pose "$city/scene.json" --image p0001 --gcp "$DIR/gcp-five.csv" -o "$DIR/posed-five.json"
expect_rc "pose: 5 points with the focal free" 2
expect_out "pose: 5 points" "5 control point\(s\).*at least 6.*--refine none"
run pose-bad pose "$city/scene.json" --image p0001 --gcp "$DIR/gcp-bad.csv" -o "$DIR/posed-bad.json"
expect_rc "pose: a CSV with a word for a number" 2
expect_out "pose: bad CSV" "gcp-bad.csv: line 3: column 'x': expected a finite number, got 'thirty'"
check "pose: nothing written on error" test ! -e "$DIR/posed-bad.json"
# GeoPose (docs/pose.md): the demo is in Lambert-93, about 0.5 degree of longitude west of its
# central meridian, so the grid is the local east-north-up frame within a meridian convergence of
# about 0.5 degree: the GeoPose forward axis (the quaternion's y) is the camera's viewing direction
# (its rotation's third row) in the grid within 1 degree, and the position lies in Paris.
run pose-geopose pose "$city/scene.json" --image p0001 --gcp "$DIR/gcp.csv" --start "$DIR/pose-start.json" \
  -o "$DIR/posed-gp.json" --geopose "$DIR/posed.geopose.json"
expect_rc "pose --geopose" 0
check "pose --geopose: Basic-Quaternion layout, in Paris, forward axis the camera's" python3 - "$DIR/posed.geopose.json" "$DIR/posed-gp.json" <<'PY'
import json, math, sys
g = json.load(open(sys.argv[1]))
c = json.load(open(sys.argv[2]))["cameras"][0]
assert sorted(g) == ["position", "quaternion"], g
assert sorted(g["position"]) == ["h", "lat", "lon"] and sorted(g["quaternion"]) == ["w", "x", "y", "z"], g
lat, lon, h = (g["position"][k] for k in ("lat", "lon", "h"))
x, y, z, w = (g["quaternion"][k] for k in "xyzw")
assert abs(x * x + y * y + z * z + w * w - 1) < 1e-9
fwd = (2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w))   # the rotation's second column
cam = c["rotation"][6:9]   # the camera's z axis in the world (its rotation's third row)
deg = math.degrees(math.acos(max(-1.0, min(1.0, sum(a * b for a, b in zip(fwd, cam))))))
print(f"lat {lat:.6f} lon {lon:.6f} h {h:.2f}; forward axis {deg:.3f} deg from the camera's in the grid")
sys.exit(0 if 48.7 < lat < 49.0 and 2.2 < lon < 2.5 and abs(h - c["center"][2]) < 1e-6 and deg < 1.0 else 1)
PY
python3 -c 'import json, sys; s = json.load(open(sys.argv[1])); s.pop("crs"); json.dump(s, open(sys.argv[2], "w"))' \
  "$city/scene.json" "$city/scene-nocrs.json"
run pose-geopose-nocrs pose "$city/scene-nocrs.json" --image p0001 --gcp "$DIR/gcp.csv" -o "$DIR/posed-nocrs.json" \
  --geopose "$DIR/nocrs.geopose.json"
expect_rc "pose --geopose: a scene without a CRS" 2
expect_out "pose --geopose: no CRS" "--geopose: .*scene-nocrs.json has no CRS"
check "pose --geopose: nothing written without a CRS" test ! -e "$DIR/nocrs.geopose.json"

# --- catalog load: what fails without a server (the rest, with one: ctest -R '^catalog$')
run catalog-file catalog load "$city/scene.json" "$DIR/cameras.json"
expect_rc "catalog load: a file path for the database" 2
expect_out "catalog load: a file path" "expected a PostgreSQL connection, \"postgresql://"
run catalog-down catalog load "$city/scene.json" "postgresql://postgres:s3cret@127.0.0.1:1/postgres"
expect_rc "catalog load: nobody listens on the port" 1
expect_out "catalog load: nobody listens" "postgresql://postgres:\*\*\*@127.0.0.1:1/postgres: cannot connect"
check "catalog load: the password is not printed" bash -c "! grep -q s3cret '$out'"
run catalog-table catalog load "$city/scene.json" "postgresql://postgres@127.0.0.1:1/postgres" --table "x;drop"
expect_rc "catalog load: a table name that would be SQL" 2
expect_out "catalog load: bad table" "--table: expected a table name"
python3 - "$city/scene.json" "$DIR/catalog-both.json" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["cameras"]["postgis"] = "postgresql://postgres@127.0.0.1:1/postgres"
json.dump(scene, open(sys.argv[2], "w"))
PY
run catalog-both info "$DIR/catalog-both.json"
expect_out "scene.json: cameras.path and cameras.postgis" "cameras.path: not with cameras.postgis"

echo "cli test took $((SECONDS - t0)) s"
echo "$passed passed, $failed failed"
((failed == 0))
