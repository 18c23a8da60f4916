// The plain description of one frame that the GL renderer consumes (docs/design.md, steps 1, 4):
// which photographs texture the view, with which weights, in which texture slices, with their
// packed per-image parameters. No GL here: everything is CPU-testable.
#pragma once

#include "hv/camera/camera.h"
#include "hv/camera/frustum.h"
#include "hv/ibr/selection.h"
#include "hv/scene/scene.h"
#include "hv/util/dates.h"

#include <glm/glm.hpp>

#include <optional>
#include <array>
#include <string>
#include <vector>

namespace hv::ibr {

enum class BlendMethod { Blend, Nearest };

struct BlendSettings {
  int k = 8;                  // images blended
  double sigma = -1.0;        // f(d) = 1/(sigma^2 + d^2); <= 0: the scene's camera spacing
  BlendMethod method = BlendMethod::Blend;
  bool occlusion = true;      // depth-map (shadow) test
  bool masks = true;
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
  Camera view;                          // world frame
  std::vector<SelectedImage> images;    // the K nearest, ascending distance
  double nextDistance = -1.0;           // d_{K+1}; < 0 when there were K or fewer candidates
  double sigma = 1.0;
  BlendSettings settings;
};

// `bounds` clips the view frustum for the frustum filter (usually the scene's geometry bounds).
FramePlan planFrame(const Scene& scene, const CameraIndex& index, const Camera& view, const BlendSettings& settings,
                    const Aabb& bounds);

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
//   t5     : uvScale (xy), slice, weight
//   t6     : depth rect: pxMin (xy), 1/(pxMax - pxMin) (zw)
//   t7     : near, far, bias (absolute, scene units), bias (relative to depth)
//   t8     : the photograph's date interval (days since 1970-01-01, hv/util/dates.h; +-kOpenDay when
//            undated), 0, 0
//   t9     : distortion scale (xy), tangential p1, p2
//   t10    : fish-eye affine l1, l2, model (0 polynomial, 1 fish-eye), 0
inline constexpr int kTexelsPerImage = 11;
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
  DateInterval date;  // the photograph's (open when undated)
};

ImageParams makeImageParams(const Camera& camera, const glm::dvec3& origin, const SliceLayout& layout, double weight,
                            const PinholeFrustum& depth, const DepthBias& bias);
void packImageParams(const ImageParams& p, float* out /* kTexelsPerImage * 4 floats */);

}  // namespace hv::ibr
