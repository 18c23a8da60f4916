#!/usr/bin/env bash
# GLSL validation without a GL context (ctest: `shader_validate`, label "cpu").
#
#   tests/shader_validate.sh path/to/hv_shader_dump [scratch-dir]
#
# hv_shader_dump writes every stage the renderer compiles, assembled as gpu::Program assembles it
# (includes and defines resolved, the naive binding generated); glslangValidator (Debian
# glslang-tools) then checks each one as GLSL ES 3.00, the WebGL2 subset: the `#version 300 es`
# line, checked here first, selects that profile. Exits 77 (ctest SKIP_RETURN_CODE) when
# glslangValidator is missing. Prints "N passed, M failed" and exits non-zero when one failed.
set -uo pipefail

DUMP=${1:?usage: shader_validate.sh path/to/hv_shader_dump [scratch-dir]}
DIR=${2:-$(mktemp -d "${TMPDIR:-/tmp}/hv-shader-validate.XXXXXX")}

if ! command -v glslangValidator >/dev/null 2>&1; then
  echo "SKIPPED: glslangValidator not found (Debian glslang-tools)"
  exit 77
fi

rm -rf "$DIR"
mkdir -p "$DIR"
if ! "$DUMP" "$DIR"; then
  echo "FAIL  hv_shader_dump could not assemble the shaders"
  exit 1
fi

passed=0
failed=0
shopt -s nullglob
for f in "$DIR"/*.vert "$DIR"/*.frag; do
  name=$(basename "$f")
  stage=${f##*.}
  if [[ $(head -n 1 "$f") != "#version 300 es" ]]; then
    failed=$((failed + 1))
    echo "FAIL  $name: the first line is not '#version 300 es'"
    continue
  fi
  if log=$(glslangValidator --stdin -S "$stage" <"$f" 2>&1); then
    passed=$((passed + 1))
    echo "ok    $name"
  else
    failed=$((failed + 1))
    echo "FAIL  $name"
    echo "$log" | sed 's/^/      /'
  fi
done
echo "$passed passed, $failed failed"
# No stage at all would be a broken dump, not a pass.
((passed > 0 && failed == 0))
