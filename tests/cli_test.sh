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

# --- --size: same aspect works, another aspect is refused with a message
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
run aspect render "$city/scene.json" --views "$city/views.json" --out "$DIR/r100" --size 100x100 --k 4
expect_rc size-100x100 fail
expect_out size-100x100 "aspect"

# --- eval: table with a mean row, JSON with the methods
run eval eval "$city/scene.json" --views "$city/views.json" --truth "$city/truth" --method blend,nearest \
  --json "$DIR/e.json" --k 4
expect_rc eval 0
expect_out eval "mean"
expect_out eval "nearest"
expect_out eval "mean +blend +[0-9]"
check "eval wrote e.json with \"methods\"" grep -q '"methods"' "$DIR/e.json"

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
# field) and left out, the scene still renders every view, the exit code says "input errors" (1).
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
expect_rc "render with one bad photo camera" 1
expect_out "render with one bad photo camera" "cameras-badrot.json.*$badphoto.*rotation"
for id in "${ids[@]}"; do
  check "bad photo camera: view $id still written" test -s "$DIR/rbadphoto/$id.png"
done

run badrot-view render "$city/scene.json" --views "$city/views-badrot.json" --out "$DIR/rbadview" --k 4 --size 160x120
expect_rc "render with one bad view camera" 1
expect_out "render with one bad view camera" "views-badrot.json.*$badview.*rotation"
check "bad view camera: not rendered" test ! -e "$DIR/rbadview/$badview.png"
for id in "${ids[@]:1}"; do
  check "bad view camera: good view $id still written" test -s "$DIR/rbadview/$id.png"
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
expect_rc "cameras convert (micmac, one image missing)" 1
expect_out "cameras convert (micmac, one image missing)" "Orientation-missing.jpg.xml.*missing.jpg.*not found"
expect_out "cameras convert (micmac, one image missing)" "wrote 1 camera"
check "cameras convert (micmac): centre in Lambert-93" python3 - "$mm/out/cameras.json" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))["cameras"][0]
x, y, z = c["center"]
assert 100000 < x < 1300000 and 6000000 < y < 7200000, c["center"]
PY
run info-micmac info "$mm/scene.json"
expect_out "info (micmac)" "Lambert-93 \\(EPSG:2154\\)"
expect_out "info (micmac)" "cameras from .*EPSG:4978"

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

echo "cli test took $((SECONDS - t0)) s"
echo "$passed passed, $failed failed"
((failed == 0))
