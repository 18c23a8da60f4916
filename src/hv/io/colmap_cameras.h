// COLMAP text models (cameras.txt, images.txt): the most common output of structure from motion.
// Conventions (COLMAP's documentation, "Output format"): images.txt gives cam_from_world as a
// quaternion (QW QX QY QZ, Hamilton, w first) and a translation T: x_cam = R X + T, so the centre
// is C = -R^T T; camera x right, y down, z forward; pixels with the origin at the image's top-left
// corner and the centre of the top-left pixel at (0.5, 0.5), as histoview's.
// Camera models: SIMPLE_PINHOLE (f, cx, cy), PINHOLE (fx, fy, cx, cy), SIMPLE_RADIAL (f, cx, cy, k),
// RADIAL (f, cx, cy, k1, k2). COLMAP's radial model distorts normalised coordinates u = (p - c)/f:
// u_d = u (1 + k1 |u|^2 + k2 |u|^4), which in pixels is histoview's radial polynomial about c with
// c3 = k1 / f^2, c5 = k2 / f^4, c7 = 0; its domain is cut where the polynomial stops being
// monotonic (1 + 3 c3 r^2 + 5 c5 r^4 > 0). Other models (OPENCV's tangential terms, fish-eyes) are
// reported and skipped: they need lens models this version does not have.
#pragma once

#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <string>
#include <vector>

namespace hv {

// `modelDir` holds cameras.txt and images.txt; `imageDir` the photographs (NAME relative to it).
std::vector<Photo> readColmapModel(const std::string& modelDir, const std::string& imageDir, Diagnostics& diag,
                                   bool checkImageFiles = true);

// The largest r^2 (pixels^2) below which r (1 + c3 r^2 + c5 r^4) is increasing; `fallback` when it
// increases everywhere.
double monotonicRadius2(double c3, double c5, double fallback);

}  // namespace hv
