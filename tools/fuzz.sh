#!/usr/bin/env bash
# Fuzzing with libFuzzer (clang, ASan + UBSan): builds build-fuzz/ with -DHV_FUZZ=ON and runs each
# fuzz target of fuzz/ (or the one named) for SECONDS seconds (default 60) on its seed corpus.
#
#   tools/fuzz.sh                      # every target, 60 s each
#   tools/fuzz.sh footprints 600       # one target, 10 minutes
#   tools/fuzz.sh all 300 -jobs=2      # extra arguments go to libFuzzer
#   tools/fuzz.sh scene_json 120 -fork=1 -ignore_crashes=1   # keep going past a known crash
#
# Targets: cameras_json image_decode scene_json footprints micmac_xml las ply web_points colmap_text itowns
# mesh gdal_raster ogr_vector gcp_csv cityjson colour_corrections trajectories_csv sumo_fcd gltf
# number_list iiif_info pnts tileset
# (fuzz/CMakeLists.txt). New inputs found go to
# build-fuzz/corpus/<target>/ (not into the source tree); crashes to build-fuzz/artifacts/<target>/
# as crash-*/leak-*/timeout-*/oom-*. A crash worth keeping goes into fuzz/corpus/<target>/ (named
# crash-*) once fixed, so that the ctest test fuzz_regress_<target> replays it forever.
# Exit status: 0 when no target found anything, 1 otherwise. See docs/testing.md.
set -euo pipefail
cd "$(dirname "$0")/.."

all_targets=(cameras_json image_decode scene_json footprints micmac_xml las ply web_points colmap_text itowns mesh gdal_raster ogr_vector gcp_csv cityjson colour_corrections trajectories_csv sumo_fcd gltf number_list iiif_info pnts tileset)
target=${1:-all}
seconds=${2:-60}
shift $(($# > 2 ? 2 : $#))
extra=("$@")

if [[ $target == all ]]; then
  targets=("${all_targets[@]}")
elif [[ " ${all_targets[*]} " == *" $target "* ]]; then
  targets=("$target")
else
  echo "unknown target '$target' (expected one of: all ${all_targets[*]})" >&2
  exit 2
fi

# clang with libFuzzer and the sanitizer runtimes (Debian's clang package ships them).
if ! command -v clang++ >/dev/null || ! command -v clang >/dev/null; then
  echo "installing clang"
  sudo_=""
  if [[ $(id -u) -ne 0 ]]; then sudo_="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo_ apt-get update -qq
  $sudo_ apt-get install -y -qq --no-install-recommends clang libclang-rt-dev >/dev/null
fi
bash tools/install-deps.sh

cmake -S . -B build-fuzz -G Ninja -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHV_FUZZ=ON -DHV_BUILD_TESTS=OFF -DHV_BUILD_BENCH=OFF >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target "${targets[@]/#/fuzz_}"

# LeakSanitizer on: a leak per input is a finding too (libFuzzer checks after each input).
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# Leaks inside system libraries histoview cannot free (tools/lsan.supp: the GL driver, Assimp).
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tools/lsan.supp:print_suppressions=0}
export HV_LOG=${HV_LOG:-error}

found=()
for t in "${targets[@]}"; do
  work=build-fuzz/corpus/$t
  artifacts=build-fuzz/artifacts/$t
  mkdir -p "$work" "$artifacts"
  # Seeds into the work corpus; crash-* regression cases stay out (libFuzzer stops at the first
  # crash, even while loading the corpus): ctest's fuzz_regress_<target> replays those.
  find "fuzz/corpus/$t" -maxdepth 1 -type f ! -name 'crash-*' -exec cp -n {} "$work/" \;
  echo "=== fuzz_$t for ${seconds}s (seeds fuzz/corpus/$t -> $work, artifacts in $artifacts/)"
  start=$SECONDS
  set +e
  build-fuzz/fuzz/fuzz_"$t" -max_total_time="$seconds" -timeout=30 -rss_limit_mb=4096 -max_len=65536 \
    -print_final_stats=1 -artifact_prefix="$artifacts/" "${extra[@]}" "$work" \
    >"$artifacts/fuzz.log" 2>&1
  rc=$?
  set -e
  grep -E "^(#[0-9]+ +DONE|stat::number_of_executed_units|stat::peak_rss_mb)|ERROR|SUMMARY" "$artifacts/fuzz.log" | tail -6 || true
  echo "    exit $rc after $((SECONDS - start)) s; log: $artifacts/fuzz.log"
  if ((rc != 0)); then
    found+=("$t")
    ls -1 "$artifacts" | grep -E "^(crash|leak|timeout|oom|slow-unit)-" | sed "s|^|    found: $artifacts/|" || true
  fi
done

if ((${#found[@]})); then
  echo "fuzzing found problems in: ${found[*]}"
  echo "reproduce: build-fuzz/fuzz/fuzz_<target> <artifact>"
  exit 1
fi
echo "fuzzing found nothing (${targets[*]}, ${seconds}s each)"
