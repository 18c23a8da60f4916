#!/usr/bin/env bash
# The test suite (the README's test command; CI runs it, .ci/run): installs what it needs, builds,
# and runs, each step timed (the table printed at the end, also when a step fails):
#
#   deps        tools/install-deps.sh, and the browser test's tools: Emscripten, Chromium, Node.js, npm
#   build       build/ (tools/build.sh, RelWithDebInfo, through ccache)
#   colmap      a real COLMAP model for the COLMAP reader's tests, when colmap and the data are here
#   tests       every ctest test but the browser's: CPU, GL on Mesa llvmpipe (headless EGL, no GPU
#               needed), CLI, viewer (Xvfb), fuzz corpus replays
#   web-build   the browser version: tools/web-build.sh (emcmake, emcc through ccache) into build-web/
#   web-npm     playwright-core into tests/web/node_modules (npm ci from the committed
#               package-lock.json; it drives Debian's Chromium and never downloads a browser)
#   web         the browser tests by name, `ctest -R '^web(_services)?$'` (tests/web_test.sh, headless Chromium;
#               tests/web_services_test.sh, the page reading the local service stack)
#   asan-build  build-asan/ as tools/sanitize.sh makes it (ASan + UBSan, Debug): the test binaries
#   asan-cpu    the CPU tests under ASan + UBSan + LSan (hv_tests, one process)
#   asan-fuzz   the fuzz corpus replays under the sanitizers
#   asan-gl     a named subset of the GL tests under the sanitizers (HV_ASAN_GL_FILTER)
#
# Everything under the sanitizers is `bash tools/sanitize.sh` (~17 min); the soak test is
# `bash tools/soak.sh` (docs/testing.md). In CI (CI=true) the browser test fails instead of
# skipping. Tests that use ../shared/data (HISTOVIEW_DATA) skip when it is absent, and must find
# what they read when it is there (HISTOVIEW_REQUIRE_DATA=1).
set -euo pipefail
cd "$(dirname "$0")/.."
export HV_LOG=${HV_LOG:-error}

# The GL tests run under the sanitizers: small synthetic scenes (the renderer's pixel checks, the
# lens models, the colour texture), seconds under ASan, where the demo-city, point and panorama
# tests take over 10 minutes (docs/testing.md).
HV_ASAN_GL_FILTER=${HV_ASAN_GL_FILTER:-'RendererGlTest.*:LensGlTest.*:ColorTextureGlTest.*'}

# ---- step timing ------------------------------------------------------------------------------
step_names=()
step_seconds=()
current=""
report() {
  local status=$?
  ((${#step_names[@]})) || [[ -n $current ]] || return 0
  echo
  printf '%-12s %8s\n' step seconds
  local i total=0
  for i in "${!step_names[@]}"; do
    printf '%-12s %8s\n' "${step_names[$i]}" "${step_seconds[$i]}"
    total=$((total + step_seconds[i]))
  done
  if [[ -n $current ]]; then
    printf '%-12s %8s  FAILED (exit %s)\n' "$current" $((SECONDS - current_start)) "$status"
    total=$((total + SECONDS - current_start))
  fi
  printf '%-12s %8s\n' total "$total"
}
trap report EXIT
# step NAME COMMAND...: runs COMMAND, timed under NAME; a failure ends the run (set -e).
step() {
  current=$1
  current_start=$SECONDS
  shift
  echo "=== $current"
  "$@"
  step_names+=("$current")
  step_seconds+=($((SECONDS - current_start)))
  current=""
}

# ---- the steps --------------------------------------------------------------------------------
# apt-get install, as root or through sudo.
apt_install() {
  local sudo_=""
  [[ $(id -u) -eq 0 ]] || sudo_=sudo
  echo "installing: $*"
  export DEBIAN_FRONTEND=noninteractive
  $sudo_ apt-get update -qq
  $sudo_ apt-get install -y -qq --no-install-recommends "$@" >/dev/null
}

deps() {
  bash tools/install-deps.sh
  # The browser test's tools, looked for by command: Node.js and npm may come from elsewhere than
  # Debian (NodeSource's nodejs bundles its own npm, and Debian's npm package conflicts with it).
  local need missing=()
  for need in emcc:emscripten chromium:chromium node:nodejs npm:npm; do
    command -v "${need%%:*}" >/dev/null 2>&1 || missing+=("${need#*:}")
  done
  ((${#missing[@]} == 0)) || apt_install "${missing[@]}"
}

colmap_model() {
  # A real COLMAP model of the Sceaux photographs for the COLMAP reader's tests, when colmap and
  # the real data are on this machine (made once into build/; exit 77 = skipped, the tests skip too).
  local status=0
  bash tools/colmap-sceaux.sh build/colmap-sceaux || status=$?
  [[ $status == 0 || $status == 77 ]]
  if [[ $status == 0 ]]; then export HV_COLMAP_SCEAUX=$PWD/build/colmap-sceaux/sparse; fi
}

ctest_build() {
  (cd build && ctest --output-on-failure -j"$(nproc)" --timeout 900 "$@")
}

web_npm() {
  # npm ci only when the installed playwright-core is not the locked one (npm ci always starts
  # from an empty node_modules).
  local want have
  want=$(node -p "require('./tests/web/package-lock.json').packages['node_modules/playwright-core'].version")
  have=$(node -p "try { require('./tests/web/node_modules/playwright-core/package.json').version } catch { '' }")
  if [[ $want != "$have" ]]; then
    (cd tests/web && npm ci --no-audit --no-fund --loglevel=error)
  fi
  echo "playwright-core $want"
}

web_test() {
  local log=build/web-ctest.log
  # HV_WEB_PREPARE: built and installed just above; the test brings the build up to date itself.
  HV_WEB_PREPARE=1 ctest_build -R '^web(_services)?$' --no-tests=error 2>&1 | tee "$log"
  if grep -q 'Skipped' "$log"; then
    case ${CI:-} in
      1 | true | TRUE | True | yes) echo "the browser test skipped in CI"; return 1 ;;
      *) echo "note: the browser test was SKIPPED (see its output above)" ;;
    esac
  fi
}

asan_build() {
  local targets
  # Configure first, then the test binaries and every fuzz corpus replay driver the build defines.
  bash tools/sanitize.sh --build-only hv_tests hv_gltests
  mapfile -t targets < <(ninja -C build-asan -t targets all | grep -o '^fuzz_[a-z0-9_]*_replay' | sort -u)
  bash tools/sanitize.sh --build-only "${targets[@]}"
}

# The CPU tests in one process: a process per test (ctest) takes 2.5 times as long under ASan,
# each one loading the sanitizer runtime and the libraries again (docs/testing.md).
# Without the real datasets: the tests that read them ran in the native step, and at -O0 under
# ASan the largest of them (the Paris panoramas' seams, ~10 s natively) take many minutes.
# The CPU tests draw nothing, so the GL driver is not preloaded (HV_SANITIZE_NO_PRELOAD): a preload
# would put the sanitizer runtime into the programs they start (SUMO's tools, bash, PostgreSQL),
# whose own leaks would then fail them.
asan_cpu() {
  (export HV_SANITIZE_NO_PRELOAD=1 && source tools/sanitizer-env.sh build-asan && cd build-asan &&
    HISTOVIEW_DATA=/nonexistent HISTOVIEW_REQUIRE_DATA=0 ./hv_tests --gtest_filter=-TerrainWmts.*)  # TerrainWmts: with its server, ctest terrain_wmts
}

asan_ctest() {
  (source tools/sanitizer-env.sh build-asan && cd build-asan &&
    ctest --output-on-failure -j"$(nproc)" --timeout 1800 --no-tests=error "$@")
}

asan_gl() {
  local count
  count=$(build-asan/hv_gltests --gtest_list_tests --gtest_filter="$HV_ASAN_GL_FILTER" | grep -c '^  ' || true)
  if ((count == 0)); then
    echo "HV_ASAN_GL_FILTER '$HV_ASAN_GL_FILTER' selects no GL test"
    return 1
  fi
  echo "$count GL tests: $HV_ASAN_GL_FILTER"
  (source tools/sanitizer-env.sh build-asan && cd build-asan && ./hv_gltests --gtest_filter="$HV_ASAN_GL_FILTER")
}

step deps deps
step build bash tools/build.sh -DHV_BUILD_BENCH=OFF
step colmap colmap_model
# Where the real data is present, the tests that read it must find it: a skip there would hide a
# broken path (hv::testing::dataRequired).
if [[ -d ${HISTOVIEW_DATA:-../shared/data} ]]; then export HISTOVIEW_REQUIRE_DATA=${HISTOVIEW_REQUIRE_DATA:-1}; fi
step tests ctest_build -E '^web(_services)?$'
step web-build bash tools/web-build.sh
step web-npm web_npm
step web web_test
step asan-build asan_build
step asan-cpu asan_cpu
step asan-fuzz asan_ctest -L fuzz
step asan-gl asan_gl
