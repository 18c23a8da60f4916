// Visibility layers completed from whole-object layers found another way (Layered projective
// texture maps, 2003, §4.1): the GL pass (render/layer_peeling.h) peels whole objects until the
// first cycle; the CPU reference (visibility_layers.h) finishes on the per-pixel hit lists.
#pragma once

#include "hv/layers/visibility_layers.h"

#include <cstdint>
#include <vector>

namespace hv::layers {

// layerOfObject[o] is object o's 1-based layer, 0 for an object left to this function. Each hit of
// a given object takes its object's layer (layers no hit is in are dropped and the rest
// renumbered); the hits left are then peeled as peelVisibilityLayers does, after those layers
// (cycles included). Throws std::invalid_argument as peelVisibilityLayers does.
VisibilityLayers completeVisibilityLayers(const PixelHits& hits, const std::vector<std::uint16_t>& layerOfObject);

}  // namespace hv::layers
