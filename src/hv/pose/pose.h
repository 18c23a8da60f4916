// Posing a photograph from control points (docs/pose.md): the camera whose projection puts each
// control point's world position on its pixel. Robust: RANSAC (Fischler & Bolles 1981) over
// minimal solutions — three points with the intrinsics known (Grunert's P3P, as reviewed by
// Haralick et al. 1994), six with the focal unknown (the direct linear transform, with Hartley's
// normalisation) — then Levenberg–Marquardt (Eigen's MINPACK port) on every inlier, over the
// centre, the rotation, the focal (fx = fy) and, on request, the principal point and two radial
// coefficients. Plain C++ and Eigen: the native and browser builds share it.
#pragma once

#include "hv/camera/camera.h"
#include "hv/pose/control_points.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace hv::pose {

// What the solution may change beyond the centre and the rotation.
struct Refine {
  bool focal = true;
  bool principal = false;
  bool radial = false;  // k1, k2 about the principal point, normalised by the focal (COLMAP's RADIAL)
};
// "focal,principal,radial" (any subset, comma-separated) or "none". Throws InputError naming the
// unknown word.
Refine parseRefine(const std::string& list);

struct PoseOptions {
  Refine refine;
  double inlierPixels = 0.0;  // a point is an inlier within this distance; 0: 0.5 % of the image diagonal, at least 2
  int maxIterations = 2000;   // RANSAC samples at most (fewer once the inliers found make more pointless)
  std::uint64_t seed = 1;
};

struct PoseResult {
  Camera camera;
  std::vector<double> residuals;  // pixels, per control point (all of them, outliers too)
  std::vector<bool> inliers;
  int inlierCount = 0;
  double rmsPixels = 0.0;                // over the inliers
  glm::dvec3 centerSigma{0.0};           // one standard deviation of the centre, world units
  double rotationSigmaDegrees = 0.0;     // of the rotation angle, the largest axis
  double focalSigma = 0.0;               // pixels (0 when the focal is not solved)
  std::vector<std::string> notes;        // how it was solved (degenerate cases said)
};

// The intrinsics of `start` (size, principal point, distortion; the focal unless it is refined
// and no better guess exists) are kept except where `options.refine` frees them; when
// `startPose` is true, its centre and rotation are a first guess too (a camera with a rough
// position). Throws InputError saying what to add when the points cannot determine the unknowns:
// too few for them, collinear world points, too few inliers, a critical configuration.
PoseResult solvePose(const std::vector<ControlPoint>& points, const Camera& start, bool startPose,
                     const PoseOptions& options);

// The minimal solvers, for tests. A pose is (camFromWorld, centre).
using Pose = std::pair<glm::dmat3, glm::dvec3>;
// Up to four poses from three unit bearing vectors in the camera frame and their world points.
std::vector<Pose> solveP3P(const std::array<glm::dvec3, 3>& bearings, const std::array<glm::dvec3, 3>& world);
// The camera of the direct linear transform (n >= 6 points not all on a plane): pose, focal
// (the mean of fx and fy) and principal point; false when the system is degenerate.
struct DltCamera {
  Pose pose;
  double focal = 0.0;
  glm::dvec2 principal{0.0};
};
bool solveDlt(const std::vector<glm::dvec2>& pixels, const std::vector<glm::dvec3>& world, DltCamera& out);

}  // namespace hv::pose
