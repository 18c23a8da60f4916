// Colour maps for debug images people look at.
#pragma once

#include "hv/image/image.h"

namespace hv {

// Counts (0 = black) to a perceptually ordered ramp (dark blue -> green -> yellow -> white), scaled
// to the largest count in the image.
Image8 colorMapCounts(const Image16& counts);

}  // namespace hv
