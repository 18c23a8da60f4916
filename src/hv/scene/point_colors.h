// How an untextured point is shown: its own colour, from the
// attribute the cloud carries. Plain data for the renderer's point buffer.
#pragma once

#include "hv/scene/point_cloud.h"

#include <glm/glm.hpp>
#include <glm/gtc/type_precision.hpp>

#include <cstdint>
#include <vector>

namespace hv {

enum class PointColorMode {
  Auto,            // RGB when present, else the class colour, else intensity, else grey
  Rgb,             // the point's RGB (grey where absent)
  Intensity,       // grey from the intensity, stretched between its 2nd and 98th percentiles
  Classification,  // the ASPRS class palette (classColor)
};

// The palette of the usual ASPRS classes (LAS 1.4 R15 table 17): ground brown, vegetation greens,
// buildings red, water blue, roads dark grey; other classes a stable colour of their own.
glm::u8vec3 classColor(std::uint8_t asprsClass);

// Per point: the display colour (rgb) and the class (a; 1 "unclassified" without classification).
std::vector<glm::u8vec4> pointDisplayColors(const PointCloud& cloud, PointColorMode mode);

}  // namespace hv
