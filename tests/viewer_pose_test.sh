#!/usr/bin/env bash
# End-to-end test of the viewer's pose mode (ctest: `viewer_pose`, labels "viewer" and "gl").
#
#   tests/viewer_pose_test.sh path/to/histoview [scratch-dir]
#
# A demo city whose photograph's camera is wrong (its centre moved 6 m): the viewer opens at the
# photograph's true camera (a --views entry), and a pose script (--pose-script, docs/viewer.md)
# enters pose mode at that photograph and clicks pairs — a pixel of the photograph, then the same
# pixel of the window, which the viewer turns into a world point by an Embree ray cast through its
# view — then saves. The saved camera must be the true one (centre within 0.1 m, rotation within
# 0.1 degree) and not the scene's. Then saving over the viewer's own scene.json must be refused
# (exit 2, the file untouched), and so must an existing file without "replace".
# Exits 77 (skipped) when xvfb-run or the viewer is not available, saying which.
set -uo pipefail

HV=${1:?usage: viewer_pose_test.sh path/to/histoview [scratch-dir]}
HV=$(cd "$(dirname "$HV")" && pwd)/$(basename "$HV")
DIR=${2:-$(mktemp -d "${TMPDIR:-/tmp}/hv-viewer-pose-test.XXXXXX")}
source "$(dirname "$0")/viewer_common.sh"
photo=p0001

# wrong.json: the scene with the photograph's centre moved; truth.json: its true camera as a view;
# the script: 12 pixels over the lower part of the photograph (the streets and façades, not the
# sky), each clicked on the photograph and then in the window (the same pixel of the same camera).
read -r w h < <(python3 - "$city" "$photo" "$DIR" <<'EOF2'
import json, sys
city, photo, out = sys.argv[1:4]
cams = json.load(open(f"{city}/cameras.json"))
truth = next(c for c in cams["cameras"] if c["id"] == photo)
view = dict(truth, id="truth")
json.dump({"cameras": [view]}, open(f"{out}/truth.json", "w"))
for c in cams["cameras"]:
    if c["id"] == photo:
        c["center"] = [c["center"][0] + 4.0, c["center"][1] - 4.0, c["center"][2] + 2.0]
json.dump(cams, open(f"{city}/cameras-wrong.json", "w"))
scene = json.load(open(f"{city}/scene.json"))
scene["cameras"]["path"] = "cameras-wrong.json"
json.dump(scene, open(f"{city}/wrong.json", "w"))
w, h = truth["width"], truth["height"]
with open(f"{out}/pose.txt", "w") as f:
    f.write(f"enter {photo}\n")
    for i in range(4):
        for j in range(3):
            u, v = (0.08 + 0.28 * i) * w + 0.5, (0.72 + 0.1 * j) * h + 0.5
            f.write(f"photo {u} {v}\nview {u} {v}\n")
    f.write(f"save {out}/posed.json\n")
print(w, h)
EOF2
)
[[ -n ${w:-} ]] || { echo "FAIL: could not prepare the scene"; exit 1; }

view() {  # view OUT SCRIPT: the viewer at the true camera, the window the photograph's size
  xvfb-run -a -s "-screen 0 1024x768x24" "$HV" view "$city/wrong.json" --views "$DIR/truth.json" --camera truth \
    --size "${w}x${h}" --pose-script "$2" --exit-after-converge --frames 400 --hide-panel >"$DIR/$1" 2>&1
}
view pose.out "$DIR/pose.txt"
rc=$?
grep -E "^pose:" "$DIR/pose.out"
if ((rc != 0)) || [[ ! -s $DIR/posed.json ]]; then
  echo "FAIL: histoview view --pose-script exited with $rc (or saved nothing); output:"
  tail -30 "$DIR/pose.out"
  exit 1
fi
python3 - "$DIR/posed.json" "$DIR/truth.json" "$city/cameras-wrong.json" "$photo" <<'EOF2' || exit 1
import json, math, sys
posed = json.load(open(sys.argv[1]))["cameras"]
truth = json.load(open(sys.argv[2]))["cameras"][0]
wrong = next(c for c in json.load(open(sys.argv[3]))["cameras"] if c["id"] == sys.argv[4])
if len(posed) != 1 or posed[0]["id"] != sys.argv[4]:
    print("FAIL: expected one camera", sys.argv[4], "in", sys.argv[1]); sys.exit(1)
p = posed[0]
dc = math.dist(p["center"], truth["center"])
# The angle of R_p R_t^T (rotation: 9 numbers, rows of camFromWorld).
A, B = p["rotation"], truth["rotation"]
tr = sum(A[3 * i + k] * B[3 * i + k] for i in range(3) for k in range(3))
deg = math.degrees(math.acos(max(-1.0, min(1.0, (tr - 1) / 2))))
print(f"posed {sys.argv[4]}: centre {dc:.4f} m from the truth ({math.dist(wrong['center'], truth['center']):.2f} m "
      f"before), rotation {deg:.4f} deg; focal kept: {p['focal'] == truth['focal']}")
if not (dc < 0.1 and deg < 0.1 and p["focal"] == truth["focal"]):
    print("FAIL: the posed camera is not the true one (0.1 m, 0.1 deg)"); sys.exit(1)
EOF2

# Never over the viewer's inputs, and an existing file only with "replace".
cp "$city/wrong.json" "$DIR/wrong.before"
{ echo "enter $photo"; grep -E "^(photo|view)" "$DIR/pose.txt" | head -n 8; echo "save $city/wrong.json replace"; } \
  >"$DIR/refuse.txt"
view refuse.out "$DIR/refuse.txt"
rc=$?
if ((rc != 2)) || ! grep -q "input files" "$DIR/refuse.out" || ! cmp -s "$city/wrong.json" "$DIR/wrong.before"; then
  echo "FAIL: saving over scene.json: expected exit 2, 'input files' and the file untouched (exit $rc); output:"
  tail -10 "$DIR/refuse.out"
  exit 1
fi
echo "saving over the viewer's scene.json: refused"
{ echo "enter $photo"; grep -E "^(photo|view)" "$DIR/pose.txt" | head -n 8; echo "save $DIR/posed.json"; } \
  >"$DIR/exists.txt"
cp "$DIR/posed.json" "$DIR/posed.before"
view exists.out "$DIR/exists.txt"
rc=$?
if ((rc != 2)) || ! grep -q "exists" "$DIR/exists.out" || ! cmp -s "$DIR/posed.json" "$DIR/posed.before"; then
  echo "FAIL: saving over an existing file without replace: expected exit 2 and the file untouched (exit $rc)"
  tail -10 "$DIR/exists.out"
  exit 1
fi
echo "saving over an existing file without \"replace\": refused"
echo "ok"
