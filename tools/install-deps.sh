#!/usr/bin/env bash
# Installs the Debian 12 packages histoview needs to build and test. Idempotent: installs only
# what is missing, and runs `apt-get update` only when something is.
set -euo pipefail

packages=(
  cmake ninja-build g++ pkg-config ccache
  libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri   # headless GLES 3 (EGL + Mesa llvmpipe)
  libgdal-dev libproj-dev libgeos-dev                   # rasters, vectors, CRSs; LOD1 triangulation
  libembree-dev                                         # CPU ray casting (demo ground truth, tests)
  libassimp-dev                                         # arbitrary meshes (PLY, OBJ, glTF)
  libpugixml-dev                                        # MicMac orientation and calibration XML
  libglm-dev libeigen3-dev nlohmann-json3-dev libnanoflann-dev libcli11-dev
  libstb-dev libpng-dev
  libgtest-dev libbenchmark-dev
  glslang-tools                                         # glslangValidator: GLSL ES 3.00 checked offline (shader_validate)
  libglfw3-dev libimgui-dev                             # the desktop viewer (histoview view): window, UI panel
  xvfb xauth                                            # the viewer's test runs it on a virtual X display
  xdotool                                               # ... and taps keys in it (key events, not polling)
  glslang-tools                                         # glslangValidator: the shaders checked as GLSL ES 3.00
  python3                                               # the CLI, viewer and browser tests' helpers
  libzip-dev                                            # OpenRaster (.ora) files of histoview layers: zip archives
  lighttpd                                              # tools/services.sh: the HTTP front of the local OGC stack (127.0.0.1)
  cgi-mapserver                                         # ... mapserv: WCS/WMS for the DTM, WFS + OGC API Features for footprints
  mapserver-bin                                         # ... map2img, to check the generated mapfile by hand (docs/services.md)
  postgresql-15                                         # the camera catalog's tests: a private cluster (tools/catalog.sh)
  postgresql-15-postgis-3                               # ... with PostGIS (the cameras' centres, their GiST indexes)
  sumo sumo-tools                                       # the demo's traffic: netconvert, randomTrips.py, sumo --fcd-output
  libtinygltf-dev                                       # glTF vehicle models (scene.json traffic.models): tinygltf, header-only
  iipimage-server                                       # iipsrv: the IIIF image service of tools/services.sh and tests/iiif_test.sh
  mapcache-cgi                                          # MapCache: the orthophoto's WMTS in tools/services.sh and tests/orthophoto_wmts_test.sh
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  exit 0
fi
echo "installing: ${missing[*]}"
sudo_=""
if [[ $(id -u) -ne 0 ]]; then sudo_="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo_ apt-get update -qq
$sudo_ apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
