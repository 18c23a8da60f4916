#!/usr/bin/env bash
# Builds the browser version (docs/web.md): the portable modules + apps/web/hv_web.cpp with Debian's
# Emscripten (emcmake, emcc) into build-web/dist/histoview_web.{js,wasm}, compiling through ccache
# when it is installed (EM_COMPILER_WRAPPER, tools/ccache-env.sh). Installs emscripten (apt) when
# missing.
#   bash tools/web-build.sh [extra cmake arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
packages=(emscripten libglm-dev nlohmann-json3-dev libnanoflann-dev libeigen3-dev libstb-dev cmake ninja-build)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  sudo_=""
  if [[ $(id -u) -ne 0 ]]; then sudo_="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo_ apt-get update -qq
  $sudo_ apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
# Debian's emcc needs its node modules (acorn) from the system path.
export NODE_PATH=${NODE_PATH:-/usr/share/nodejs}
source tools/ccache-env.sh
mkdir -p build-web
if [[ ! -f build-web/CMakeCache.txt ]]; then
  emcmake cmake -S . -B build-web -G Ninja -DCMAKE_BUILD_TYPE=Release "$@"
fi
cmake --build build-web -j"${HV_JOBS:-$(nproc)}" -- -k 0
# proj4js for the page (docs/services.md, "In the browser": the EPSG:4978 fit of a service scene
# without a web export), pinned in tools/web-deps/package.json, installed once (again only when the
# pinned version changes) and copied beside the module; web-export copies it with the page. Without
# npm or the registry the page still works: such a scene's earth-centred points then need "files".
deps=tools/web-deps
want=$(sed -n 's/.*"proj4": "\([^"]*\)".*/\1/p' $deps/package.json)
# (nothing installed yet: sed fails, which pipefail and -e must not turn into the script's end)
have=$(sed -n 's/^ *"version": "\([^"]*\)".*/\1/p' $deps/node_modules/proj4/package.json 2>/dev/null | head -1 || true)
if [[ $have != "$want" ]] && command -v npm >/dev/null; then
  (cd $deps && npm ci --no-audit --no-fund >/dev/null) || echo "web-build: proj4 $want not installed (npm failed)" >&2
fi
if [[ -f $deps/node_modules/proj4/dist/proj4.js ]]; then
  cp $deps/node_modules/proj4/dist/proj4.js build-web/dist/proj4.js
fi
ls -l build-web/dist/histoview_web.js build-web/dist/histoview_web.wasm
