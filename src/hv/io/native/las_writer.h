// Writes point clouds as uncompressed LAS (for the demo city's simulated scan and for tests).
#pragma once

#include "hv/scene/point_cloud.h"

#include <optional>
#include <string>

namespace hv {

struct LasWriteOptions {
  int minorVersion = 2;  // LAS 1.<minor>: 2 (1.2) or 4 (1.4)
  int pointFormat = -1;  // 0-10; -1: 3 when the cloud has RGB, else 1
  glm::dvec3 scale{0.001};
  std::optional<glm::dvec3> offset;  // default: the bounds' minimum, rounded down to metres
};

// Writes positions (quantised to `scale`), intensity, classification and RGB where the format has
// them (missing attributes are written as 0), return 1 of 1, GPS time 0, and the CRS: "EPSG:<n>"
// as a GeoTIFF keys VLR (a projected CRS code), anything else as an OGC WKT VLR. Throws
// std::invalid_argument for an impossible request (format 6-10 in LAS 1.2, a class above 31 in
// formats 0-5, coordinates that do not fit in 32 bits at that scale) and std::runtime_error when
// the file cannot be written.
void writeLas(const std::string& path, const PointCloud& cloud, const LasWriteOptions& options = {});
// The same into memory.
std::string lasBytes(const PointCloud& cloud, const LasWriteOptions& options = {});

}  // namespace hv
