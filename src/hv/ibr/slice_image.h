// How a photograph is put into its texture slice (docs/design.md, step 2): scaled (never up) to fit
// the slice, padded with transparent texels, the mask in alpha, colour premultiplied by alpha.
// Plain C++ so the tests can build exactly what the GPU samples.
#pragma once

#include "hv/ibr/frame_plan.h"
#include "hv/image/image.h"

namespace hv::ibr {

struct SliceSize {
  int width = 0, height = 0;
};

// The scale s <= 1 a camera's image gets in a slice, and the resulting uv scale.
SliceLayout sliceLayout(const Camera& camera, SliceSize slice, int sliceIndex);

// `photo` RGB(A) of any size with the camera's aspect ratio; `mask` 1 channel (0 = discard) or
// empty. Throws InputError when the photo's aspect ratio does not match the camera's.
Image8 makeSliceImage(const Camera& camera, const Image8& photo, const Image8& mask, SliceSize slice,
                      const std::string& nameForErrors);

}  // namespace hv::ibr
