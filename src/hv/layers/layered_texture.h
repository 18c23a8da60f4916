// Rendering a photograph's edited layers (Layered projective texture maps, 2003, §5), CPU
// reference: each sub-image is a projective texture through its sheared frustum (its window of the
// photograph, hv/layers/sub_image.h), applied to the objects of its own visibility layer only.
//
// The paper applies each sub-image to its objects by drawing them with that texture bound. A
// renderer that draws the whole scene once and textures each fragment from its photographs (Brédif
// 2013) has no object to bind per draw, so here the "own objects" rule is a per-point test against
// a *peeled depth map*: D_k, the depth map of visibility layer k, holds at each pixel of the
// photograph the nearest surface of the objects of layers >= k along its ray (the ray goes on
// through the objects of layers < k). A layer-k sub-image textures a point P only where P lies *on*
// that surface (a two-sided depth test: not behind it, as the photographs' shadow test asks, and
// not in front of it either):
//   - a façade hidden in the photograph, in layer 2, is the nearest surface of layers >= 2, so the
//     layer-2 sub-image (painted by the artist) textures it; it is behind D_1 (the occluder), so the
//     layer-1 sub-image (the photograph) does not;
//   - the occluder in front, in layer 1, is on D_1; it is in front of D_2, so the painting never
//     lands on it.
// Because the layers are peeled in visibility order, the nearest surface of layers >= k on a ray is
// one of layer k's objects wherever layer k has something on that ray, and a deeper layer's
// otherwise; there layer k's sub-image is transparent (its alpha is the mask), so it adds nothing.
// No geometry is subdivided and one depth map per visibility layer serves all its sub-images.
//
// The photograph's contribution at P is the first sub-image, in visibility-layer order then in the
// file's order, whose window holds P's projection, whose layer's depth test P passes, and whose
// texel is not transparent; it is blended with the other photographs as the photograph itself would
// be (its weight, hv::ibr::BlendOptions::layered).
#pragma once

#include "hv/camera/camera.h"
#include "hv/image/image.h"
#include "hv/layers/sub_image.h"
#include "hv/layers/visibility_layers.h"

#include <glm/glm.hpp>

#include <optional>
#include <vector>

namespace hv::layers {

// D_k: per pixel (row-major) the distance from the camera centre, along the pixel's unit ray, of
// the nearest surface of layers >= k; +infinity where there is none.
struct PeeledDepthMap {
  int layer = 0;  // k, 1-based
  int width = 0, height = 0;
  std::vector<float> distance;
};

// D_k from the per-pixel hit lists and their layers (peelVisibilityLayers). `layer` >= 1.
PeeledDepthMap peeledDepthMap(const PixelHits& hits, const VisibilityLayers& visibility, int layer);

struct LayeredSubImage {
  int visibilityLayer = 0;  // k
  SubImageWindow window;    // the photograph's (distorted) pixels
  Image8 rgba;              // straight alpha, any resolution (the window stretched over it)
};

// The depth test's tolerance: the four texels of D_k that a bilinear lookup at P reads (those with
// a surface) give a range of distances, widened by metres + relative * distance (the ray casts'
// float precision and the edited file's rounding of windows). The range, rather than the nearest
// texel, follows a surface seen at a grazing angle across a texel without its normal.
struct LayeredDepthTolerance {
  double metres = 0.05;
  double relative = 2e-3;
};

struct LayeredPhotograph {
  Camera camera;  // the photograph's, at its own size (the windows' pixels)
  std::vector<LayeredSubImage> subImages;
  // D_1 .. D_n at the size the layers were made at (the photograph's aspect ratio): depthMaps[k-1].
  std::vector<PeeledDepthMap> depthMaps;
  LayeredDepthTolerance tolerance;
};

// Whether the world point at distance `distance` from the camera, projected at `pxDistorted` (the
// photograph's pixels), lies on D_k's surface (the two-sided test above).
bool onPeeledSurface(const LayeredPhotograph& photo, int layer, glm::dvec2 pxDistorted, double distance);

// The premultiplied RGBA in [0, 1] the edited layers give at `worldPoint` (bilinear, clamp to the
// window's edge, texel centres at (i + 0.5) / size as GL_LINEAR), or nullopt when no sub-image
// textures it (outside every window, on no layer's surface, or transparent there).
std::optional<glm::dvec4> layeredTexel(const LayeredPhotograph& photo, const glm::dvec3& worldPoint);

}  // namespace hv::layers
