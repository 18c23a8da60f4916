// The programs of the GPU layer peeling (render/layer_peeling.h, render/gl/layer_peel_pass.cpp),
// for that pass and for programSources() (the list the shader test checks).
#pragma once

#include "hv/render/renderer.h"

namespace hv::render::gl {

struct LayerPeelSources {
  ProgramSource terrain;  // where each ray enters and leaves the ground
  ProgramSource item;     // the item buffer of the working set
  ProgramSource test;     // the occlusion test (the inverted depth test), one query per object
};
const LayerPeelSources& layerPeelPrograms();

}  // namespace hv::render::gl
