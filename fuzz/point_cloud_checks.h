// What scene loading does with the cloud a point reader returned, for the point fuzz targets (LAS,
// PLY, the browser's points.bin): its attributes must be consistent (else abort: a reader bug),
// then it is organised into chunks and chunks are selected for a view.
#pragma once

#include "hv/scene/chunks.h"

#include <cstdlib>
#include <functional>

namespace hv::fuzz {

// `afterOrganise` (optional) runs between the chunking and the selection (e.g. a subsample).
inline void organiseAndSelect(PointCloud& cloud, const std::function<void(PointCloud&)>& afterOrganise = {}) {
  if (!cloud.consistent()) std::abort();
  organizeChunks(cloud, {.maxPointsPerChunk = 64});
  if (afterOrganise) afterOrganise(cloud);
  const Aabb b = cloud.bounds();
  // A camera needs room: at huge coordinates the look-at offset vanishes in rounding.
  if (b.empty() || !(glm::length(b.center()) < 1e9 && glm::length(b.size()) < 1e9)) return;
  const Camera view = lookAtCamera("v", b.center() + glm::dvec3(1.0, -50.0, 20.0), b.center(), 64, 48, 50.0);
  (void)selectChunks(cloud, view, 100);
}

}  // namespace hv::fuzz
