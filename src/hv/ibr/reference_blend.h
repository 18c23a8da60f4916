// CPU reference of the per-fragment blend (docs/design.md, step 5). It is the specification the
// mesh shader (shaders/ibr_shade.frag, `hv_blend`) is tested against at sampled pixels.
#pragma once

#include "hv/ibr/frame_plan.h"
#include "hv/ibr/weights.h"
#include "hv/image/image.h"

#include <functional>
#include <optional>
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

// Mask alpha of slice `slice` at `uv`, trilinear at mip level `lod` of the slice's chain (sliceMipChain).
using MaskLookup = std::function<double(int slice, glm::dvec2 uv, double lod)>;

// What the geometry weights and the feathering need besides the images (BlendSettings' fields and
// the pixel's geometry); the defaults are the papers' blend.
struct BlendOptions {
  Weighting weighting = Weighting::Distance;
  double resolutionWeight = 0.5;
  double penaltyEpsilon = 0.05;
  // Geometry weighting: the images blended per pixel (geometryBlendCount with k); 0: k.
  int geometryK = 0;
  double featherPx = 0.0;
  // Transient filter (consensusWeights): the kernel's spread in RGB; 0: off.
  double consensusSpread = 0.0;
  glm::dvec3 viewCenter{0.0};  // render frame
  double viewFocal = 1.0;      // pixels
  glm::dvec3 normal{0.0, 0.0, 1.0};
  // Feathering toward mask edges: the mask averaged over the feather width; null: none.
  MaskLookup mask;
  int sliceWidth = 1;  // texels, to turn the feather width into a mip level
  // Layered photographs (Layered projective texture maps, 2003, §5; hv/layers/layered_texture.h):
  // per image, empty for a photograph as it is; otherwise what its edited layers give at the point
  // (render frame), premultiplied, nullopt where no sub-image textures it. It stands for the
  // photograph's shadow test, texture lookup and mask (the sub-images' own depth test and alpha);
  // the projection, the image bounds, the colour correction and the weight stay the photograph's.
  std::vector<std::function<std::optional<glm::dvec4>(const glm::dvec3& pointRender)>> layered;
};

// Distance, in photograph pixels, of a projection to the photograph's border and (distorted
// photographs) to the edge of its lens domain, measured in ideal pixels along the radius.
double borderDistance(const ImageParams& image, const ImageHit& hit);
// The mip level whose texels span the feather width: log2(featherPx * uvScale.x * sliceWidth), >= 0.
double featherLevel(const ImageParams& image, double featherPx, int sliceWidth);

// A premultiplied texel through the image's colour correction: straight colour c becomes
// clamp(gain c + offset, 0, 1). Twin of hv_correctColour in shaders/ibr_common.glsl.
glm::dvec4 correctTexel(const ColourCorrection& colour, const glm::dvec4& texel);

// `images` in ascending distance to the view. Global selection: each image's weight is its w_i.
// Region selection (Buehler et al. 2001's per-pixel best k, Brédif 2013's weights): each image's
// weight is f(d_i); the first `k` images that pass every test (projection, visibility, mask
// alpha > 0) contribute w_i = f(d_i) - f(d_K+1), d_K+1 the distance of the K+1-th that passes at
// this point (f = 0 when none does). Nearest: the first that passes, either way.
// Geometry weighting (either selection): every image that passes is ranked by its penalty
// p_i (hv/ibr/weights.h), ties in list order; the first K = geometryBlendCount(k, geometryK)
// blend with f(p_i) - f(p_K+1), f with sigma = penaltyEpsilon. Feathering multiplies each weight by featherFactor(borderDistance) and,
// with a mask lookup, maskFeather of the mask at featherLevel. The transient filter
// (consensusWeights, blend only) then reweights the first kMaxConsensusSamples contributing images.
BlendResult referenceBlend(const glm::dvec3& pointRender, const std::vector<ImageParams>& images, BlendMethod method,
                           const TextureLookup& texture, const VisibilityTest& visible,
                           Selection selection = Selection::Global, int k = 0, const BlendOptions& options = {});

// Bilinear lookup with clamp-to-edge and texel centres at (i + 0.5) / size, as GL_LINEAR does,
// of an RGBA8 image; returns values in [0, 1].
glm::dvec4 sampleBilinear(const Image8& rgba, glm::dvec2 uv);
// GL_LINEAR_MIPMAP_LINEAR at an explicit level of detail (clamped to the chain) of a mip chain
// (ibr::sliceMipChain): the bilinear lookups of the two levels around `lod`, mixed linearly.
glm::dvec4 sampleTrilinear(const std::vector<Image8>& chain, glm::dvec2 uv, double lod);

}  // namespace hv::ibr
