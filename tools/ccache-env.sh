# Sourced (not run) by the build scripts: compile through ccache when it is installed
# (tools/install-deps.sh installs it), so that a rebuild of unchanged sources, in any checkout of
# the project on this machine and in any of its builds (build/, build-asan/, build-web/), is a
# cache hit.
#
# Sets hv_launcher, the CMake arguments for native builds (empty without ccache), and exports
# EM_COMPILER_WRAPPER, through which Emscripten's emcc runs its clang (emcc reads it per compile,
# so it applies whatever way build-web/ was configured).
hv_launcher=()
if command -v ccache >/dev/null; then
  # Paths below the project's parent folder are hashed relative to it, so another checkout or a
  # fresh clone beside it hits the same entries.
  CCACHE_BASEDIR=${CCACHE_BASEDIR:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)}
  export CCACHE_BASEDIR
  export CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-1}
  export EM_COMPILER_WRAPPER=${EM_COMPILER_WRAPPER:-ccache}
  hv_launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
