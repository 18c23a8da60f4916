# Sourced (not run) before running anything built in build-asan/ (tools/sanitize.sh, and the
# sanitizer steps of tools/test.sh): the sanitizers' options and the GL driver preload below.
#   source tools/sanitizer-env.sh [BUILD_DIR]      (default build-asan, relative to the repository)
# LeakSanitizer is on; its suppressions (tools/lsan.supp) may only name system libraries (the GL driver, Assimp).
# UBSan stops at its first report, so that a finding fails the test instead of scrolling past.
hv_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
hv_asan_dir=${1:-build-asan}
[[ $hv_asan_dir == /* ]] || hv_asan_dir=$hv_root/$hv_asan_dir
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$hv_root/tools/lsan.supp:print_suppressions=0}
export HV_LOG=${HV_LOG:-error}

# Mesa loads its llvmpipe driver with dlopen and unloads it at eglTerminate/exit, before the leak
# check: its one-time allocations then show up as leaks from "<unknown module>" that no suppression
# can name. Preloading the driver keeps it mapped, so what it still holds stays reachable (and any
# real leak in it is reported with its library name, for tools/lsan.supp). With GCC, libasan must
# come first in the preload list.
hv_driver=$(ls /usr/lib/*-linux-gnu/dri/swrast_dri.so /usr/lib/*-linux-gnu/libgallium*.so 2>/dev/null | head -1 || true)
if [[ -n $hv_driver && -z ${HV_SANITIZE_NO_PRELOAD:-} && ${LD_PRELOAD:-} != *"$hv_driver"* ]]; then
  hv_asan_rt=$(ldd "$hv_asan_dir/hv_tests" 2>/dev/null | awk '/libasan\.so/ {print $3; exit}')
  export LD_PRELOAD="${hv_asan_rt:+$hv_asan_rt }$hv_driver${LD_PRELOAD:+ $LD_PRELOAD}"
  echo "LD_PRELOAD=$LD_PRELOAD"
fi
