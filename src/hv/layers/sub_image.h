// Sub-image projective textures (Layered projective texture maps, 2003, §5.1): a sub-image is a
// window of a photograph, textured through a *sheared* frustum, the photograph's frustum cut down
// to that window (the paper's glFrustum with x'min = xmin + xi (xmax - xmin) / w, ...).
//
// Windows are in the photograph's pixels (hv/camera/camera.h), i.e. *distorted* pixels, where the
// photograph (and so an exported layer) is looked up. The frusta of the renderer are pinhole
// frusta in *ideal* (undistorted) pixels (hv/camera/frustum.h), and the shader looks the texture
// up at distort(ideal pixel). So the sheared frustum of a window is the ideal rectangle covering
// it: the window itself without distortion (then its [-1, 1]^2 is exactly the window), the box of
// its undistorted border with distortion; the texture coordinate is (distort(px) - window.min) /
// window.size in both cases (subImageUv), the same steps as the whole photograph's.
#pragma once

#include "hv/camera/camera.h"
#include "hv/camera/frustum.h"

#include <glm/glm.hpp>

#include <optional>

namespace hv::layers {

struct SubImageWindow {
  glm::dvec2 pxMin{0.0}, pxMax{0.0};  // photograph pixels (distorted), pxMin < pxMax
  glm::dvec2 size() const { return pxMax - pxMin; }
};

// The sheared frustum of a window: its ideal pixel rectangle (above), with the depth range given.
// With distortion, the border is sampled every few pixels (as idealRectCoveringImage does for the
// whole image); a border point outside the lens model's domain is skipped.
PinholeFrustum subImageFrustum(const Camera& camera, const SubImageWindow& window, double near, double far);

// The paper's sheared glFrustum bounds (§5.1) from the whole photograph's frustum bounds at depth 1
// (xmin..xmax, ymin..ymax: the ideal rectangle in camera units, (px - c) / f) and the window
// (xi, yi, wi, hi) in an image of w x h pixels. For an undistorted camera, subImageFrustum's
// rectangle in camera units equals these.
struct FrustumBounds {
  double xmin = 0.0, xmax = 0.0, ymin = 0.0, ymax = 0.0;
};
FrustumBounds shearedFrustumBounds(const FrustumBounds& whole, double w, double h, const SubImageWindow& window);

// Where a render-frame point is looked up in the sub-image's texture, through the sub-image's clip
// matrix (clipFromRender(camera, frustum, origin)): clip -> NDC -> ideal pixel in the frustum's
// rectangle -> distort -> (p - window.min) / window.size. uv (0, 0) is the window's top-left
// corner. nullopt behind the camera (clip w <= 0).
std::optional<glm::dvec2> subImageUv(const Camera& camera, const PinholeFrustum& frustum, const SubImageWindow& window,
                                     const glm::dmat4& clipFromRenderMatrix, const glm::dvec3& renderPoint);

}  // namespace hv::layers
