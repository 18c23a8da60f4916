// Normals for point clouds that carry none (LAS has no normal field): the sprites of the point
// pass are planes, and a camera-facing plane (the fallback of docs/design.md, step 6) textures a
// road or a wall seen at an angle from the wrong places of each photograph.
//
// The estimate is the classic one of Hoppe et al. (1992), "Surface reconstruction from
// unorganized points", as PDAL's filters.normal and CloudCompare compute it: the direction of
// least variance (the eigenvector of the smallest eigenvalue of the covariance) of each point's k
// nearest neighbours (nanoflann kd-tree).
//
// The sign is not observable from the points alone; the point pass does not need it (N' and the
// shadow bias are unchanged by N -> -N). Normals are turned upwards (n.z >= 0), so those of
// ground and roofs point up; on walls the sign is arbitrary.
#pragma once

#include "hv/scene/point_cloud.h"

#include <functional>
#include <mutex>
#include <vector>

namespace hv {

struct NormalEstimation {
  int neighbours = 16;      // k, the point itself included
  // When the k nearest lie along a line (one scan line of a mobile-mapping scan), the estimate is
  // made again with this many, enough to reach the neighbouring scan lines.
  int wideNeighbours = 64;
  int threads = 2;          // 0: on the calling thread (the browser build has no threads)
};

// Fills cloud.normals (replacing any) for every point. A point whose neighbourhood does not span
// a plane (fewer than 3 points, or elongated: the middle spread under 5 % of the largest, with k
// and with wideNeighbours) gets (0, 0, 0): its sprite then faces the camera. Neighbours are
// distinct positions: duplicates of a point share its normal, and cost nothing more (a million
// identical points take what one does; docs/reliability.md).
void estimateNormals(PointCloud& cloud, const NormalEstimation& settings = {});

// Normals estimated when first needed: the point pass is off by default, and the estimate is a
// large part of a load. deferNormals leaves cloud.normals empty and the estimate pending
// (PointCloud::pendingNormals); pointNormals makes it on first call (once, whichever thread asks
// first: the others wait for it) over the positions as they are then: what estimateNormals would
// give, since the estimate does not depend on the points' order (each distinct position once,
// sorted). The positions must not change meanwhile (PointCloud::permute resolves first).
struct PendingNormals {
  NormalEstimation settings;
  std::once_flag once;
  std::vector<glm::vec3> normals;
};
void deferNormals(PointCloud& cloud, const NormalEstimation& settings = {});
// The cloud has normals, or will have them when asked (pointNormals).
bool hasNormals(const PointCloud& cloud);
// cloud.normals, else the pending estimate (made now if not yet), else empty. Thread-safe.
const std::vector<glm::vec3>& pointNormals(const PointCloud& cloud);
// Puts the pending estimate (made now if not yet) into cloud.normals; nothing is pending after.
void resolveNormals(PointCloud& cloud);

}  // namespace hv
