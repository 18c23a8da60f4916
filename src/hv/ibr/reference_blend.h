// CPU reference of the per-fragment blend (docs/design.md, step 5). It is the specification the
// mesh shader (shaders/ibr_shade.frag, `hv_blend`) is tested against at sampled pixels.
#pragma once

#include "hv/ibr/frame_plan.h"
#include "hv/image/image.h"

#include <functional>
#include <vector>

namespace hv::ibr {

struct BlendResult {
  glm::dvec3 color{0.0};  // normalised colour c̄ / A
  double alpha = 0.0;     // A = sum w_i a_i
  int count = 0;          // images that contributed (passed every test, alpha and weight > 0)
  // Per image (same order as the images): what it added to A, w_i a_i (nearest: 1 for the
  // winner), 0 when it did not contribute. contribution[i] / alpha is image i's share of the
  // colour (the renderer's DebugView::Weight).
  std::vector<double> contribution;
  bool covered() const { return alpha > 0.0; }
  double share(size_t image) const { return covered() ? contribution[image] / alpha : 0.0; }
};

// Premultiplied RGBA in [0, 1] of slice `slice` at texture coordinate `uv`.
using TextureLookup = std::function<glm::dvec4(int slice, glm::dvec2 uv)>;
// Whether the point (render frame), at depth `depth` along image i's axis, is seen by image i.
using VisibilityTest = std::function<bool(size_t image, const glm::dvec3& pointRender, double depth)>;

// The project-and-test part shared by every pass: where `pointRender` falls in image i, or
// nullopt when it is behind the camera, outside the distortion domain or outside the image.
struct ImageHit {
  glm::dvec2 pxIdeal{0.0}, pxDistorted{0.0};
  double depth = 0.0;
};
std::optional<ImageHit> projectIntoImage(const ImageParams& image, const glm::dvec3& pointRender);

// A premultiplied texel through the image's colour correction: straight colour c becomes
// clamp(gain c + offset, 0, 1). Twin of hv_correctColour in shaders/ibr_common.glsl.
glm::dvec4 correctTexel(const ColourCorrection& colour, const glm::dvec4& texel);

// `images` in ascending distance to the view. Global selection: each image's weight is its w_i.
// Region selection (Buehler et al. 2001's per-pixel best k, Brédif 2013's weights): each image's
// weight is f(d_i); the first `k` images that pass every test (projection, visibility, mask
// alpha > 0) contribute w_i = f(d_i) - f(d_K+1), d_K+1 the distance of the K+1-th that passes at
// this point (f = 0 when none does). Nearest: the first that passes, either way.
BlendResult referenceBlend(const glm::dvec3& pointRender, const std::vector<ImageParams>& images, BlendMethod method,
                           const TextureLookup& texture, const VisibilityTest& visible,
                           Selection selection = Selection::Global, int k = 0);

// Bilinear lookup with clamp-to-edge and texel centres at (i + 0.5) / size, as GL_LINEAR does,
// of an RGBA8 image; returns values in [0, 1].
glm::dvec4 sampleBilinear(const Image8& rgba, glm::dvec2 uv);

}  // namespace hv::ibr
