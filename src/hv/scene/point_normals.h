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

}  // namespace hv
