// COLMAP text models (cameras.txt, images.txt): the most common output of structure from motion.
// Conventions (COLMAP's documentation, "Output format"): images.txt gives cam_from_world as a
// quaternion (QW QX QY QZ, Hamilton, w first) and a translation T: x_cam = R X + T, so the centre
// is C = -R^T T; camera x right, y down, z forward; pixels with the origin at the image's top-left
// corner and the centre of the top-left pixel at (0.5, 0.5), as histoview's.
// Camera models: SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL, OPENCV (fx fy cx cy k1 k2 p1 p2),
// SIMPLE_RADIAL_FISHEYE, RADIAL_FISHEYE and OPENCV_FISHEYE (k4 = 0). COLMAP distorts normalised
// coordinates u = (p - c) / f, which is hv::LensDistortion with centre c and scale f; the fish-eyes
// are its equidistant model (theta_d = theta (1 + k1 theta^2 + ...)). Domains are fitted to where
// the radial profile increases (hv::fitLensDomain).
#pragma once

#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <string>
#include <vector>

namespace hv {

// `modelDir` holds cameras.txt and images.txt; `imageDir` the photographs (NAME relative to it).
std::vector<Photo> readColmapModel(const std::string& modelDir, const std::string& imageDir, Diagnostics& diag,
                                   bool checkImageFiles = true);

}  // namespace hv
