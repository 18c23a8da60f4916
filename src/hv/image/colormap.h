// Colour maps for debug images people look at.
#pragma once

#include "hv/image/image.h"

#include <glm/glm.hpp>

namespace hv {

// The ramp every debug view uses: t in [0, 1] (clamped) from dark purple through blue and green
// to yellow (a viridis-like ramp: perceptually ordered, readable by colour-blind people), RGB in
// [0, 1]. GLSL twin: hv_colorRamp in shaders/colormap.glsl (src/hv/render/debug_view_gltest.cpp
// checks that they agree).
glm::dvec3 colorRamp(double t);

// Counts (0 = black) to colorRamp, scaled to the largest count in the image.
Image8 colorMapCounts(const Image16& counts);

}  // namespace hv
