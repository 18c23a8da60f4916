#!/usr/bin/env bash
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer (+ LeakSanitizer): configures
# build-asan/ (Debug, -DHV_SANITIZE=ON), builds, and runs every ctest test there (CPU, GL on
# llvmpipe, CLI, fuzz corpus replay).
#
#   tools/sanitize.sh                 # everything
#   tools/sanitize.sh -L cpu          # extra arguments go to ctest (-L gl, -R fuzz_, ...)
#
# Leaks inside the Mesa/LLVM GL driver are suppressed by tools/lsan.supp (driver libraries only;
# never hv code). See docs/testing.md.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh

cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DHV_SANITIZE=ON -DHV_BUILD_BENCH=OFF >/dev/null
cmake --build build-asan -j"$(nproc)"

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tools/lsan.supp:print_suppressions=0}
export HV_LOG=${HV_LOG:-error}

# Mesa loads its llvmpipe driver with dlopen and unloads it at eglTerminate/exit, before the leak
# check: its one-time allocations then show up as leaks from "<unknown module>" that no suppression
# can name. Preloading the driver keeps it mapped, so what it still holds stays reachable (and any
# real leak in it is reported with its library name, for tools/lsan.supp). With GCC, libasan must
# come first in the preload list.
driver=$(ls /usr/lib/*-linux-gnu/dri/swrast_dri.so /usr/lib/*-linux-gnu/libgallium*.so 2>/dev/null | head -1 || true)
if [[ -n $driver && -z ${HV_SANITIZE_NO_PRELOAD:-} ]]; then
  asan_rt=$(ldd build-asan/hv_tests 2>/dev/null | awk '/libasan\.so/ {print $3; exit}')
  export LD_PRELOAD="${asan_rt:+$asan_rt }$driver${LD_PRELOAD:+ $LD_PRELOAD}"
  echo "LD_PRELOAD=$LD_PRELOAD"
fi
cd build-asan
# Sanitized Debug code is several times slower: give each test a generous timeout.
ctest --output-on-failure -j"$(nproc)" --timeout 1800 "$@"
