// The plain description of one frame that the GL renderer consumes (docs/design.md, steps 1, 4):
// which photographs texture the view, with which weights, in which texture slices, with their
// packed per-image parameters. No GL here: everything is CPU-testable.
#pragma once

#include "hv/camera/camera.h"
#include "hv/camera/frustum.h"
#include "hv/ibr/region_selection.h"
#include "hv/ibr/selection.h"
#include "hv/scene/scene.h"
#include "hv/util/dates.h"

#include <glm/glm.hpp>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace hv::ibr {

enum class BlendMethod { Blend, Nearest };

// How the photographs that texture a frame are chosen (docs/design.md, steps 1 and 5).
enum class Selection {
  // Per region (opt-in, see docs/evaluation.md for why it is not yet the default): up to
  // `candidates` photographs, so that every region of the view has its own
  // nearest ones (ibr/region_selection.h), sorted by distance to the view centre; each pixel blends
  // the first K of them that pass its tests, with weights f(d_i) - f(d_K+1) where d_K+1 is the
  // distance of the K+1-th that passes at that pixel (Buehler et al. 2001's per-pixel best k with
  // Brédif 2013's weights). SelectedImage::weight then holds f(d_i).
  Region,
  // The papers' (Brédif 2013 eq. 1-2), the default: the K nearest to the view centre for the whole
  // frame, one weight f(d_i) - f(d_K+1) each.
  Global,
};

// How each pixel weighs the photographs it blends (docs/design.md, step 5; hv/ibr/weights.h).
enum class Weighting {
  // The papers' (Brédif 2013 eq. 1-2): by the distance of the camera centre to the view centre.
  Distance,
  // Per pixel, by a penalty of the angle between the photograph's ray and the view's ray and of the
  // photograph's resolution on the surface (texel footprint against the view's pixel footprint,
  // grazing incidence included); the best K of the frame's candidates per pixel (after Buehler et
  // al. 2001). The candidates are those of the selection: region, its candidates; global, the
  // `candidates` nearest to the view.
  Geometry,
};

// The most images the geometry weights blend at one pixel (the shader's arrays hold K + 1).
inline constexpr int kMaxGeometryK = 16;
// The most candidates the shader ranks by penalty at one pixel: those of its tile list, the best
// by penalty kept when the list is longer (docs/design.md, "Weights that know geometry").
inline constexpr int kMaxGeometryRank = 32;

// How many images the geometry weights blend at one pixel: `geometryK` (0: k), at most k and
// kMaxGeometryK, at least 1.
int geometryBlendCount(int k, int geometryK);

struct BlendSettings {
  int k = 8;  // images blended at one pixel (at most)
  Weighting weighting = Weighting::Distance;
  double resolutionWeight = 0.5;  // lambda: radians of penalty per unit of ln(footprint ratio)
  double penaltyEpsilon = 0.05;   // radians: f(p) = 1/(epsilon^2 + p^2) for the geometry weights
  // Geometry weights: the images blended per pixel, the best by penalty (at most k, which keeps its
  // meaning); 0: k. SIBR's unstructured lumigraph renderer blends the best 4.
  int geometryK = 0;
  // Weights fall smoothly to 0 over this many photograph pixels toward each photograph's border,
  // lens domain edge and mask edges; 0: hard edges (the papers'). 4 by default: it takes 89 % of
  // the excess step off the photograph borders of the demo city's views for 0.03 dB of PSNR, and
  // changes no Sceaux photograph by more than 0.01 dB (docs/evaluation.md, "Seams").
  double featherPx = 4.0;
  // Transient filter (hv/ibr/consensus.h): at each pixel, images whose colour is far from the
  // others' common colour lose their weight (a Gaussian of this spread, RGB in [0, 1]); 0: off
  // (the papers').
  double consensus = 0.0;
  // Photograph slices sampled with mipmaps, the level from the projected footprint (through the
  // lens distortion), and anisotropic filtering up to `anisotropy` where the context has it; off:
  // level 0 (the papers'). Anisotropy 1 by default: Mesa's software rasteriser filters each
  // anisotropic sample in full (a demo view at 8 took minutes instead of seconds), and on the
  // Sceaux photographs the isotropic level from the footprint's area scored as well.
  bool mipmaps = false;
  double anisotropy = 1.0;
  Selection selection = Selection::Global;
  // Region: how many photographs a frame may make resident and pass to the shader (also capped by
  // the image slots). Global ignores it.
  int candidates = 24;
  RegionGrid regionGrid;  // region: how finely the view is sampled for candidates
  double sigma = -1.0;    // f(d) = 1/(sigma^2 + d^2); <= 0: the scene's camera spacing
  BlendMethod method = BlendMethod::Blend;
  bool occlusion = true;  // depth-map (shadow) test
  bool masks = true;
  // Each photograph's colour correction (Photo::colour) applied to its texels; without corrections
  // in the scene, all are the identity.
  bool colourCorrection = true;
  std::vector<std::string> exclude;  // photo ids left out (leave-one-out)
  // Only photographs that see part of the view frustum (clipped to the scene bounds) are
  // candidates, so the K slots go to images that can texture the view (docs/design.md, step 1).
  bool frustumFilter = true;
  // Time window (--from/--to): a dated photograph is a candidate when its date (the interval it
  // names, hv/util/dates.h) overlaps the window; an undated one (no date, or one parseDate
  // rejects) is a candidate unless datedOnly, which drops it with or without a window.
  std::optional<DateInterval> window;
  bool datedOnly = false;
};

struct SelectedImage {
  int photo = -1;
  double distance = 0.0;
  double weight = 0.0;
};

struct FramePlan {
  Camera view;  // world frame
  // Ascending distance. Global: the K nearest, weight f(d_i) - f(d_K+1). Region: the candidates,
  // weight f(d_i) (the shader subtracts each pixel's own f(d_K+1)).
  std::vector<SelectedImage> images;
  double nextDistance = -1.0;  // global: d_{K+1}; < 0 when there were K or fewer candidates (region: -1)
  double sigma = 1.0;
  BlendSettings settings;
};

// `bounds` clips the view frustum for the frustum filter (usually the scene's geometry bounds).
// Region selection uses `frusta` (built over the same bounds from the scene's cameras; one is
// built for the call when it is null); without geometry bounds it takes the `candidates` nearest.
FramePlan planFrame(const Scene& scene, const CameraIndex& index, const Camera& view, const BlendSettings& settings,
                    const Aabb& bounds, const FrustumIndex* frusta = nullptr);

// Where a photograph sits in the image texture array.
struct SliceLayout {
  int slice = 0;
  glm::dvec2 uvScale{1.0};  // texture uv = pxDistorted * uvScale (folds the resize into the slice)
};

// Per-image shader parameters. Layout of one image in the RGBA32F data texture (kTexelsPerImage
// texels, one row per image); the GLSL reader is `hv_fetchImage` in shaders/ibr_common.glsl:
//   t0..t2 : rows of M = K R (xyz), C_render.x / .y / .z (w)
//   t3     : distortion centre (xy), c3, c5 (hv::LensDistortion)
//   t4     : c7, r2max (< 0: no distortion), width, height
//   t5     : uvScale (xy), slice, weight (region selection: f(d_i), see Selection)
//   t6     : depth rect: pxMin (xy), 1/(pxMax - pxMin) (zw)
//   t7     : near, far, bias (absolute, scene units), bias (relative to depth)
//   t8     : the photograph's date interval (days since 1970-01-01, hv/util/dates.h; +-kOpenDay when
//            undated), focal length (pixels, mean of fx and fy), visibility layer k of a layered
//            photograph's sub-image (0: a photograph as it is)
//   t9     : distortion scale (xy), tangential p1, p2
//   t10    : fish-eye affine l1, l2, model (0 polynomial, 1 fish-eye), group (sub-images: the
//            photograph's index + 1, the same for all its sub-images; 0 otherwise)
//   t11    : colour gain (rgb), uv offset x   (hv::ColourCorrection; identity when switched off)
//   t12    : colour offset (rgb), uv offset y
// Texture uv = (pxDistorted - uvOffset) * uvScale: the offset is 0 for a photograph, its window's
// top-left corner for a sub-image (Layered projective texture maps, 2003, §5.1), whose bias terms
// (t7.zw) then hold the two-sided depth test's tolerance (metres, relative to the distance).
inline constexpr int kTexelsPerImage = 13;
// Stands for an open end of a date interval on the GPU (days; floats hold whole days exactly up
// to 2^24, so day numbers of the last and next few millennia are exact).
inline constexpr double kOpenDay = 1e7;
// A date interval as two floats for the GPU, open ends clamped to +-kOpenDay.
glm::vec2 gpuDays(const DateInterval& interval);

struct DepthBias {
  double absolute = 0.0;  // scene units
  double relative = 0.0;  // times the depth
};

// Slope-scaled shadow bias (scene units) for a point at depth z seen at `cosIncidence` =
// |n . (P - C_i)/|P - C_i|| by the photograph: absolute + relative * z * (1 + tan(theta)), with
// cos clamped at 0.1. Twin of hv_shadowBias in shaders/image_test.glsl.
double shadowBias(const DepthBias& bias, double z, double cosIncidence);

struct ImageParams {
  int photo = -1;  // index into Scene::photos (not sent to the GPU)
  glm::dmat3 pixFromWorld{1.0};
  glm::dvec3 centerRender{0.0};
  Camera camera;  // for distortion, size (world frame)
  SliceLayout layout;
  double weight = 0.0;
  PinholeFrustum depth;
  DepthBias bias;
  DateInterval date;        // the photograph's (open when undated)
  ColourCorrection colour;  // applied to its texels (identity: none)
  // A layered photograph's sub-image (render/frame_builder.h): its window's top-left corner
  // (photograph pixels), its visibility layer k >= 1 and its group (the photograph's index + 1).
  // 0 for a photograph as it is.
  glm::dvec2 uvOffset{0.0};
  int layer = 0;
  int group = 0;
};

ImageParams makeImageParams(const Camera& camera, const glm::dvec3& origin, const SliceLayout& layout, double weight,
                            const PinholeFrustum& depth, const DepthBias& bias);
void packImageParams(const ImageParams& p, float* out /* kTexelsPerImage * 4 floats */);

}  // namespace hv::ibr
