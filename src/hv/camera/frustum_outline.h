// What a photograph sees, as lines to draw in 3D (the viewer's frustum debug view): the
// border of its image unprojected to a depth, and the edges from its centre to the corners. Plain
// C++ (no GL): the renderer uploads the segments, a CPU test checks them against hand values.
//
// The border is the *distorted* image border [0,W]x[0,H] (the photograph's own edges), so a
// distorted camera's outline is curved as its depth map's coverage is. Border pixels that cannot be
// undistorted (outside the lens model's domain, LensDistortion::undistort) are pulled towards the
// principal point to the last pixel that can: the outline then follows the domain's edge, which is
// where the renderer stops using the photograph.
#pragma once

#include "hv/camera/camera.h"

#include <glm/glm.hpp>

#include <array>
#include <vector>

namespace hv {

struct FrustumOutline {
  glm::dvec3 apex{0.0};            // the camera centre, world
  std::vector<glm::dvec3> border;  // closed loop (last point joins the first), world, at `depth`
  std::array<int, 4> corners{};    // border indices of the image corners (0,0), (W,0), (W,H), (0,H)
};

// `depth` along the camera axis (scene units, > 0); `perSide` >= 1 border samples per image side
// (1: the four corners only, enough for a pinhole camera).
FrustumOutline frustumOutline(const Camera& camera, double depth, int perSide);

// GL_LINES pairs: the border loop, then the four apex-to-corner edges.
std::vector<glm::dvec3> frustumLineSegments(const FrustumOutline& outline);

}  // namespace hv
