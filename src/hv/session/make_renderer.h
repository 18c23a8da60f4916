// The renderer every command and the viewer builds for a scene (session.cpp).
#pragma once

#include "hv/render/renderer.h"
#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <memory>

namespace hv::app {

// The renderer of `scene` with `settings`, given the photographs' edited layers (scene.json
// "layers", docs/layers.md): each file read back and peeled again for the photograph's camera as it
// is now. Every renderer a command or the viewer builds for a scene comes from here (openSession;
// the viewer's rebuilds after a setting read at construction or a photograph's pose changed). A
// layers file that cannot be used is an error in `diag` (its path, why) and the photograph renders
// as itself. `orthophoto` (hv::loadOrthophoto; Session::orthophoto): draped on untextured
// terrain. Needs a current GL context.
std::unique_ptr<render::Renderer> makeRenderer(const Scene& scene, const render::RenderSettings& settings,
                                               Diagnostics& diag,
                                               std::shared_ptr<const Orthophoto> orthophoto = nullptr);

}  // namespace hv::app
