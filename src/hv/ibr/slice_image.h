// How a photograph is put into its texture slice (docs/design.md, step 2): scaled (never up) to fit
// the slice, padded with transparent texels, the mask in alpha, colour premultiplied by alpha.
// Plain C++ so the tests can build exactly what the GPU samples.
#pragma once

#include "hv/ibr/frame_plan.h"
#include "hv/image/image.h"

#include <vector>

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

// The mip levels of a slice (RGBA8, premultiplied), level 0 first, down to 1 x 1: level l + 1 is
// max(1, floor(size_l / 2)) per side, each texel the rounded mean of the 2 x 2 texels above it
// (clamped at an odd edge). What the renderer uploads, so the tests sample the same levels.
std::vector<Image8> sliceMipChain(const Image8& slice);
// The number of levels of a w x h chain: floor(log2(max(w, h))) + 1.
int mipLevelCount(int width, int height);
// Bytes of a whole RGBA8 chain of w x h (about 4/3 of level 0).
std::size_t mipChainBytes(int width, int height);

}  // namespace hv::ibr
