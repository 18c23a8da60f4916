// The interface a GPU backend implements (docs/design.md): it holds the geometry, the photographs'
// slices and depth maps in slots, and runs what a Frame (render/frame.h) asks. The frame builder
// decides everything else in plain C++. Implementations: the GLES 3.0 one (render/gl/gl_backend.h)
// and the null backend (render/null_backend.h), which draws nothing and records the calls.
#pragma once

#include "hv/ibr/slice_image.h"
#include "hv/image/image.h"
#include "hv/render/frame.h"
#include "hv/scene/orthophoto.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hv::render {

// The "building index + 1" the surfaces' vertices carry (GeometryBuffers) for the scene.json
// "mesh": neither terrain (0) nor a building (hv_surfaceExisted in shaders/image_test.glsl takes it
// as always existing); the largest 24-bit index, so that the orthophoto is draped on terrain only.
inline constexpr std::uint32_t kMeshSurfaceId = 0xFFFFFFu;

// What the context can do, as far as the frame builder sizes things with it.
struct BackendLimits {
  int maxTextureSize = 4096;
  int maxArrayTextureLayers = 256;
  int maxVaryingComponents = 60;
  // Binding::Naive: texture units free for photographs and depth maps (two per image), and the
  // units the shading pass keeps for itself (named in the warning when K exceeds the slots).
  int naiveImageUnits = 10;
  int shadingUnits = 6;
  int maxTextureImageUnits = 16;
};

// The slots the builder allocated: slice i of the image and depth-map stores holds one photograph.
struct SlotLayout {
  ibr::SliceSize slice;
  int depthSize = 0;
  int slots = 0;
  Binding binding = Binding::Array;
  // Depth-map layers the array binding allocates at first (at most `slots`): the array grows, its
  // maps copied, as higher slots are first drawn (the slot cache fills the lowest free slot first).
  int initialDepthLayers = 0;
};

// The point pass's programs: the mat3 sprite form (2016) links with as many images as the
// context's varyings allow, up to `wantImages`.
struct PointProgramRequest {
  SpriteForm form = SpriteForm::PlaneVector;
  int wantImages = 1;
  double maxPointSizePx = 64.0;
};
struct PointProgramInfo {
  int mat3Images = 0;         // > 0: the 2016 form with this many images
  float maxPointSize = 1.0f;  // pixels, also capped by ALIASED_POINT_SIZE_RANGE
};

class Backend {
 public:
  virtual ~Backend() = default;
  virtual BackendLimits limits() const = 0;

  virtual void uploadGeometry(const GeometryBuffers& geometry) = 0;
  // A tile streamed per view (terrain: render/terrain_stream.h; buildings, ids with
  // kBuildingTileId set: render/building_stream.h), in buffers of its own (GeometryBuffers' vertex
  // layout), drawn by the frames and depth-map jobs that list its id after their index ranges;
  // released when evicted.
  virtual void uploadStreamedTile(std::uint64_t id, const std::vector<float>& vertices,
                                 const std::vector<std::uint32_t>& indices) = 0;
  virtual void releaseStreamedTile(std::uint64_t id) = 0;
  // Replaces the building validity texels (GeometryBuffers::validity's layout): streamed building
  // tiles bring their buildings' dates with them.
  virtual void uploadValidity(const std::vector<float>& validity, int width, int rows) = 0;
  // The orthophoto draped on untextured terrain (Scene::orthophoto) and its map from the render
  // frame to texture coordinates; sampled where UntexturedSettings::orthophoto.
  virtual void uploadOrthophoto(const Orthophoto& orthophoto, const OrthophotoAffine& affine) = 0;
  // The point buffer, in chunk order, and the point programs. Throws when no program links.
  virtual PointProgramInfo uploadPoints(const std::vector<PointVertex>& points, const PointProgramRequest& req) = 0;
  // Allocates the slots' stores (and, for the naive binding, the program that samples them).
  virtual void allocateSlots(const SlotLayout& layout) = 0;
  // Makes a decoded photograph resident in `slot` (premultiplied RGBA, the layout's slice size).
  virtual void uploadImage(int slot, const Image8& slice) = 0;
  virtual void drawDepthMap(const DepthMapJob& job) = 0;
  // Fills the depth map of `slot` with `depth` (size x size texels, row 0 at the frustum's pxMin.y,
  // linear depth in [0, 1] between near and far, 1: no surface) instead of drawing it: a layered
  // photograph's peeled depth map D_k over its sub-image's frustum (render/frame_builder.h).
  virtual void uploadDepthMap(int slot, const std::vector<float>& depth) = 0;
  // Waits until the depth maps asked so far are drawn (a time budget is about GPU time).
  virtual void finishDepthMaps() = 0;
  // The view passes: view depth, points, tile lists, shading, debug view, overlays, read-back.
  virtual RenderOutput runViewPasses(const Frame& frame, ViewPassStats& stats) = 0;
  // The texture holding the last frame's colour (0: none).
  virtual unsigned int colorTexture() const = 0;
};

}  // namespace hv::render
