#!/usr/bin/env bash
# The soak test (docs/testing.md; not part of tools/test.sh): a long progressive walk through a
# scene of many photographs, checking that memory stays flat and nothing goes wrong on the GL side.
#
#   tools/soak.sh [PHOTOS] [FRAMES] [OUT]       (defaults: 10000 photographs, 2000 frames, build/soak)
#
# 1. Builds histoview (tools/build.sh) when build/histoview is missing.
# 2. Generates the scene in OUT/city: the demo city's terrain, buildings and lidar scan
#    (`histoview demo --generate-only`, 16 photographs), and PHOTOS synthetic photographs: each a
#    demo camera moved by up to 3 m, with that photograph box-filtered down 5 times (64x48 to
#    80x60 pixels) and its brightness changed, so that every one is its own file and its own picture.
# 3. A camera path (OUT/path.json) through the 4:3 pinhole demo cameras, timed so that `histoview fly
#    --progressive` at 25 fps renders exactly FRAMES frames (320x240, K = 8, depth maps 256²).
# 4. Runs the walk, sampling the process's resident memory (VmRSS) at every frame's progress line,
#    into OUT/rss.tsv; keeps one frame in 500 (OUT/frames/).
#
# It fails unless: fly exits 0 having written FRAMES frames (a GL error throws and ends the walk
# with exit 1; warnings or a photograph left out exit non-zero too); no "GL error" was printed;
# over the last half of the walk (at most its last 1000 frames), resident memory grew by no more
# than HV_SOAK_GROWTH_MIB (least-squares slope times the frame count; default 16 MiB, 2.5 times the
# 6.4 MiB measured at the defaults, docs/testing.md, where one leaked 320x240 frame a frame would
# be 300 MiB), and it never rose above its level at the first frame by more than the renderer's
# caps (RenderSettings: the image and depth-map budget, 1 GiB, plus the decoder's, 512 MiB).
#
# σ is given (--sigma): the median nearest-neighbour spacing of the 16 demo cameras, what the
# default would be for the demo city itself; left to its default, σ would be recomputed from all
# PHOTOS cameras at every frame (Scene::cameraSpacing, quadratic), which times the spacing and not
# the walk.
set -euo pipefail
cd "$(dirname "$0")/.."
photos=${1:-10000}
frames=${2:-2000}
out=${3:-build/soak}
export HV_LOG=${HV_LOG:-warn}
if ! [[ $photos =~ ^[0-9]+$ && $frames =~ ^[0-9]+$ ]] || ((photos < 16 || frames < 2)); then
  echo "usage: tools/soak.sh [PHOTOS >= 16] [FRAMES >= 2] [OUT]" >&2
  exit 2
fi

[[ -x build/histoview ]] || bash tools/build.sh -DHV_BUILD_BENCH=OFF
hv=$PWD/build/histoview
rm -rf "$out"
mkdir -p "$out"
out=$(cd "$out" && pwd)
start=$SECONDS

echo "=== the demo city (16 photographs) in $out/demo"
"$hv" demo --out "$out/demo" --generate-only --buildings 24 --photos 16 --views 1 >"$out/demo.log" 2>&1 ||
  { cat "$out/demo.log"; exit 1; }

echo "=== $photos synthetic photographs and a $frames-frame path"
sigma=$(python3 - "$out" "$photos" "$frames" <<'PY'
import json, math, os, random, struct, sys, zlib

out, count, frames = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
demo = os.path.join(out, "demo", "city")
city = os.path.join(out, "city")
os.makedirs(os.path.join(city, "images"), exist_ok=True)
base = json.load(open(os.path.join(demo, "cameras.json")))["cameras"]
SHRINK = 5  # the demo photographs (320x240 to 400x300) -> 64x48 to 80x60
for b in base:
    if b["width"] % SHRINK or b["height"] % SHRINK or b.get("distortion", {}).get("type", "radial") != "radial":
        raise SystemExit(f"{b['id']}: {b['width']}x{b['height']}, {b.get('distortion')}: expected sides that "
                         f"are multiples of {SHRINK} and no distortion or a radial one")

sys.path.insert(0, os.path.abspath(os.path.join("tests", "services")))  # run from the repository root
from png_read import decode_png  # the services tests' PNG decoder (standard library only)

def read_png(path):
    """8-bit RGB PNG (what the demo writes) -> (width, height, bytearray rows)."""
    w, h, channels, rows = decode_png(path)
    if channels != 3:
        raise SystemExit(f"{path}: expected an 8-bit RGB PNG, got {channels} channels")
    return w, h, rows

def shrink(w, h, rows):
    sw, sh = w // SHRINK, h // SHRINK
    small = []
    for y in range(sh):
        line = bytearray(sw * 3)
        for x in range(sw):
            for ch in range(3):
                s = sum(rows[y * SHRINK + j][(x * SHRINK + i) * 3 + ch] for j in range(SHRINK) for i in range(SHRINK))
                line[x * 3 + ch] = s // (SHRINK * SHRINK)
        small.append(line)
    return sw, sh, small

def png_bytes(w, h, raw):
    """raw: the rows, each after its filter byte (0, none)."""
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))

small = []
for c in base:
    sw, sh, rows = shrink(*read_png(os.path.join(demo, c["image"])))
    small.append((sw, sh, b"".join(b"\0" + bytes(r) for r in rows)))
rng = random.Random(1)
cameras = []
for i in range(count):
    b = base[i % len(base)]
    sw, sh, raw = small[i % len(base)]
    gain = rng.uniform(0.8, 1.2)  # 0 stays 0: the filter bytes are unchanged
    name = f"images/s{i:05d}.png"
    with open(os.path.join(city, name), "wb") as f:
        f.write(png_bytes(sw, sh, raw.translate(bytes(min(255, int(v * gain)) for v in range(256)))))
    # Intrinsics in pixels with the origin at the image's corner (docs/formats.md): they scale with
    # it, and so does the radial polynomial's centre; r' = r (1 + c3 r² + c5 r⁴ + c7 r⁶) in pixels
    # (Brédif 2013, fig. 2) keeps its shape with c_k scaled by SHRINK^(k-1).
    if "distortion" in b:
        d = dict(b["distortion"])
        d["center"] = [x / SHRINK for x in d["center"]]
        for k in ("c3", "c5", "c7"):
            if k in d: d[k] *= SHRINK ** (int(k[1]) - 1)
        if "r2max" in d: d["r2max"] /= SHRINK ** 2
        b = dict(b, distortion=d)
    c = {k: v for k, v in b.items() if k not in ("mask", "image", "id")}
    c.update(id=f"s{i:05d}", image=name, width=sw, height=sh,
             focal=[f / SHRINK for f in b["focal"]], principal=[p / SHRINK for p in b["principal"]],
             center=[b["center"][0] + rng.uniform(-3, 3), b["center"][1] + rng.uniform(-3, 3),
                     b["center"][2] + rng.uniform(-0.5, 0.5)])
    cameras.append(c)
json.dump({"cameras": cameras}, open(os.path.join(city, "cameras.json"), "w"))

scene = json.load(open(os.path.join(demo, "scene.json")))
for key in ("terrain", "buildings", "points", "orthophoto"):
    if key in scene: scene[key]["path"] = os.path.join(demo, scene[key]["path"])
# The traffic only where the demo ran SUMO (its FCD output), with the paths made absolute.
traffic = scene.pop("traffic", None)
if traffic and os.path.exists(os.path.join(demo, traffic["fcd"])):
    traffic["fcd"] = os.path.join(demo, traffic["fcd"])
    traffic["models"] = {k: os.path.join(demo, v) for k, v in traffic.get("models", {}).items()}
    scene["traffic"] = traffic
scene["cameras"] = {"path": "cameras.json"}
json.dump(scene, open(os.path.join(city, "scene.json"), "w"), indent=1)

# The path: the demo cameras in nearest-neighbour order, at 320x240 (the demo's 4:3), evenly in time
# so that fly takes floor((t_end - t0) * fps) + 1 = frames frames at 25 fps (docs/formats.md).
walk = [j for j, b in enumerate(base) if b["width"] * 3 == b["height"] * 4 and "distortion" not in b]
order, left = [walk[0]], set(walk[1:])
while left:
    last = base[order[-1]]["center"]
    nxt = min(left, key=lambda j: math.dist(last, base[j]["center"]))
    order.append(nxt)
    left.remove(nxt)
t_end = (frames - 1) / 25.0
keys = []
for n, j in enumerate(order):
    b = base[j]
    s = 320 / b["width"]
    keys.append({"id": f"k{n}", "t": t_end * n / (len(order) - 1), "width": 320, "height": round(b["height"] * s),
                 "center": b["center"], "rotation": b["rotation"],
                 "focal": [f * s for f in b["focal"]], "principal": [p * s for p in b["principal"]]})
json.dump({"cameras": keys}, open(os.path.join(out, "path.json"), "w"), indent=1)

nearest = sorted(min(math.dist(a["center"], b["center"]) for b in base if b is not a) for a in base)
print(f"{nearest[len(nearest) // 2]:.3f}")
PY
)
du -sh "$out/city/images" | awk '{print "  photographs: " $1 " on disk"}'
echo "  σ = $sigma (median nearest-neighbour spacing of the demo cameras)"
echo "  generated in $((SECONDS - start)) s"

echo "=== histoview fly --progressive: $frames frames over $photos photographs"
python3 - "$hv" "$out" "$frames" "$sigma" "${HV_SOAK_GROWTH_MIB:-16}" <<'PY'
import os, re, subprocess, sys, time

hv, out, frames, sigma, growth_mib = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4], float(sys.argv[5])
# RenderSettings' caps (src/hv/render/renderer.h): images + depth maps, and decoded slices not yet uploaded.
CAPS_MIB = 1024 + 512
cmd = [hv, "fly", os.path.join(out, "city", "scene.json"), "--path", os.path.join(out, "path.json"),
       "--out", os.path.join(out, "frames"), "--fps", "25", "--progressive", "--size", "320x240",
       "--k", "8", "--depth-size", "256", "--sigma", sigma]
print("  " + " ".join(cmd), flush=True)
log = open(os.path.join(out, "fly.log"), "wb")
t0 = time.monotonic()
p = subprocess.Popen(cmd, stdout=log, stderr=subprocess.PIPE)

def rss_kib():
    with open(f"/proc/{p.pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"): return int(line.split()[1])
    return 0

samples, other, pending = [], [], b""
progress = re.compile(rb"frame (\d+)/(\d+)")
while True:
    data = os.read(p.stderr.fileno(), 65536)
    if not data: break
    pending += data
    *pieces, pending = re.split(rb"[\r\n]", pending)
    for piece in pieces:
        m = progress.search(piece)
        if not m:
            if piece.strip(): other.append(piece.decode(errors="replace"))
            continue
        done = int(m.group(1))
        try: samples.append((done, rss_kib() / 1024.0, time.monotonic() - t0))
        except OSError: pass
        if done % 500 and done != frames:  # keep one frame in 500 and the last
            try: os.remove(os.path.join(out, "frames", f"f{done - 1:05d}.png"))
            except OSError: pass
status = p.wait()
wall = time.monotonic() - t0
log.close()
with open(os.path.join(out, "rss.tsv"), "w") as f:
    f.write("frame\trss_mib\tseconds\n")
    for s in samples: f.write(f"{s[0]}\t{s[1]:.1f}\t{s[2]:.2f}\n")
text = open(os.path.join(out, "fly.log"), errors="replace").read() + "\n".join(other)
for line in other: print("  fly: " + line)

failures = []
if status != 0: failures.append(f"histoview fly exited {status} (fly.log, and the lines above)")
if "GL error" in text: failures.append("a GL error was reported")
if not samples or samples[-1][0] != frames:
    failures.append(f"{samples[-1][0] if samples else 0} of {frames} frames rendered")
if samples:
    rss = [s[1] for s in samples]
    tail = samples[-min(1000, max(2, len(samples) // 2)):]
    n = len(tail)
    xs, ys = [s[0] for s in tail], [s[1] for s in tail]
    mx, my = sum(xs) / n, sum(ys) / n
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / max(sum((x - mx) ** 2 for x in xs), 1e-9)
    growth = slope * (xs[-1] - xs[0])
    per_frame = (samples[-1][2] - samples[0][2]) / max(len(samples) - 1, 1)
    print(f"  frames {samples[-1][0]}, wall {wall:.1f} s (scene load and first frame {samples[0][2]:.1f} s, "
          f"then {1000 * per_frame:.0f} ms per frame)")
    print(f"  RSS MiB: first frame {rss[0]:.1f}, peak {max(rss):.1f} (frame {samples[rss.index(max(rss))][0]}), "
          f"last {rss[-1]:.1f}")
    print(f"  last {n} frames ({xs[0]}..{xs[-1]}): RSS {min(ys):.1f}..{max(ys):.1f} MiB, "
          f"least-squares growth {growth:+.1f} MiB (bound {growth_mib:g})")
    if growth > growth_mib:
        failures.append(f"resident memory grew by {growth:.1f} MiB over the last {n} frames (bound {growth_mib:g} MiB)")
    if max(rss) - rss[0] > CAPS_MIB:
        failures.append(f"resident memory rose {max(rss) - rss[0]:.0f} MiB above the first frame's, more than the "
                        f"renderer's caps ({CAPS_MIB} MiB)")
for f in failures: print("FAIL: " + f)
print("soak: " + ("FAILED" if failures else "passed") + f" (RSS per frame in {out}/rss.tsv)")
sys.exit(1 if failures else 0)
PY
