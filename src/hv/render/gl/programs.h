// The programs the GL passes link, each named (not an index into a list). programSources()
// (render/renderer.h), the list the shader test walks, is made of these.
#pragma once

#include "hv/gpu/gl.h"
#include "hv/render/renderer.h"

namespace hv::render::gl {

struct ProgramSources {
  ProgramSource depth;       // photographs' depth maps
  ProgramSource viewDepth;   // the view's depth and building ids
  ProgramSource shade;       // the blend
  ProgramSource tileDepth;   // tile depth ranges for culling
  ProgramSource naive;       // the naive baseline, with a count any ES 3.0 context has units for
  ProgramSource pointDepth;  // point sprites into depth maps and the view
  ProgramSource pointColor;  // textured sprites, 2022 form (N')
  ProgramSource pointMat3;   // the 2016 form (the renderer picks K)
  ProgramSource debugDepth;  // DebugView::DepthMap
  ProgramSource lines;       // DebugSettings::frusta
};
const ProgramSources& programs();

// Links `src`, with `extraDefines` after its own.
gpu::Program linkProgram(const ProgramSource& src, const std::vector<std::string>& extraDefines = {});

}  // namespace hv::render::gl
