// Shader assembly without a GL context: the text a program's stage is compiled from, so that it
// can be tested on the CPU and validated offline (tests/shader_validate.sh runs glslangValidator
// on every stage as GLSL ES 3.00). gpu::Program (hv/gpu/gl.h) compiles exactly this text.
#pragma once

#include <string>
#include <vector>

namespace hv::gpu {

// A shader given as text rather than by embedded file name (generated sources, tests); its
// `#include "x.glsl"` lines still resolve to embedded files.
struct ShaderText {
  std::string name;  // for messages
  std::string source;
};

// The full source a stage is compiled from:
// - `#include "x.glsl"` lines are replaced by the embedded file shaders/x.glsl;
// - `#include "generated:NAME"` lines by text generated here from the defines (below);
// - `defines` ("NAME" or "NAME=VALUE") are inserted right after the #version line.
// Throws std::runtime_error naming the shader and what is missing or malformed.
std::string preprocessShader(const std::string& file, const std::vector<std::string>& defines);
std::string preprocessShader(const ShaderText& shader, const std::vector<std::string>& defines);

// `#include "generated:naive_binding"`: the naive binding (Brédif 2013; de Castro & Brédif 2022
// §2.1, the baseline without texture arrays) for `count` images: a sampler2D pair u_image<i>,
// u_depth<i> per image, and hv_naiveBlend(P, normal, existed, b), one call of hv_naiveStep (defined
// by shaders/ibr_shade.frag) per pair, unrolled because GLSL ES 3.00 indexes sampler arrays only
// with constant expressions. `count` comes from the define HV_NAIVE_COUNT=N; when it is absent the
// text is empty (the include sits under #ifdef HV_NAIVE). Throws unless count >= 1.
std::string naiveBindingGlsl(int count);

}  // namespace hv::gpu
