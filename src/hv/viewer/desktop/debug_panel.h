// The viewer panel's Debug section below the settings' widgets (docs/viewer.md): what the debug
// view (render::DebugSettings) shows, the chosen photograph's state, and the frame's images with
// their slot, distance, weight and residency.
#pragma once

#include "hv/render/renderer.h"

namespace hv::viewer {

// Draws it for the renderer's last frame; a click in the images table chooses that photograph
// (debug.photo) and returns true.
bool drawDebugState(const render::Renderer& renderer, const Scene& scene, render::DebugSettings& debug);

// "not resident", "decoding", "depth map pending", "ready", "broken".
const char* photoStateName(render::PhotoState state);

}  // namespace hv::viewer
