// Camera paths for `histoview fly`: key cameras at given times, and the
// cameras in between.
//
// PATH.json is a cameras.json (docs/formats.md; `image` optional) whose cameras may carry a time
// `t` in seconds. A key without `t` comes 1 s after the previous key (the first at 0 s); times
// must increase strictly. Every key shares one image size (a frame sequence has one size).
//
// Between keys, at time t in [t_i, t_i+1], with s = (t - t_i) / (t_i+1 - t_i):
// - position: the cubic Hermite curve through the key centres with Catmull-Rom tangents
//   m_i = (p_i+1 - p_i-1) / (t_i+1 - t_i-1) (Catmull & Rom 1974; the finite-difference form for
//   non-uniform times, e.g. Wikipedia "Cubic Hermite spline", § Catmull-Rom spline). The spline's
//   parameter is time itself, so the camera keeps the path's timing; with evenly spaced times it
//   is the *uniform* Catmull-Rom spline. Not the centripetal variant: that one re-parametrises by
//   distance, which would not respect the key times. The end points are duplicated (p_-1 = p_0 at
//   t_-1 = t_0, likewise at the end), which makes the end tangents the one-sided differences, so
//   evenly spaced keys on a line are travelled at constant velocity end to end.
// - rotation: spherical linear interpolation of the key rotations as unit quaternions (Shoemake
//   1985), along the shorter arc, renormalised so the matrix stays orthonormal.
// - focal, principal point, skew: linear in s; distortion: the earlier key's (the last key's at
//   the last key time).
#pragma once

#include "hv/camera/camera.h"
#include "hv/util/diagnostics.h"

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace hv {

struct PathKey {
  Camera camera;
  double time = 0.0;  // seconds
};

class CameraPath {
 public:
  // Throws InputError naming the key (camera id) and field when the keys are not a path: none,
  // times not strictly increasing or not finite, sizes that differ, a reflection.
  explicit CameraPath(std::vector<PathKey> keys);

  const std::vector<PathKey>& keys() const { return keys_; }
  double startTime() const { return keys_.front().time; }
  double endTime() const { return keys_.back().time; }

  // The camera at time t (clamped to [startTime, endTime]); its id is empty.
  Camera at(double t) const;
  glm::dvec3 position(double t) const;

 private:
  std::vector<PathKey> keys_;
  size_t segment(double t) const;  // i such that t_i <= t <= t_i+1 (0 for a single key)
};

// The most frames one path may have: 11 hours at 25 fps. More is a mistyped --fps or `t`, and
// would take weeks to render (a frame of a real scene takes 0.1 to 1 s).
inline constexpr int kMaxPathFrames = 1'000'000;

// Frames at t0, t0 + 1/fps, ... up to and including the last key time:
// floor((tEnd - t0) * fps) + 1 of them (the product is nudged by 1e-9 so that, e.g., 0.3 s at
// 10 fps gives 4 frames despite 0.3 * 10 = 2.9999999999999996). fps must be positive. Throws
// std::invalid_argument naming the count, the path's duration and kMaxPathFrames when there would
// be more than that.
int pathFrameCount(const CameraPath& path, double fps);

// The frames of a path, made one at a time when asked for (a long path is never held whole):
// frame i is the camera at t0 + i / fps, id frameId(i).
class PathFrames {
 public:
  PathFrames(CameraPath path, double fps);  // throws as pathFrameCount
  int size() const { return count_; }
  Camera operator[](int index) const;  // index in [0, size())

 private:
  CameraPath path_;
  double fps_;
  int count_;
};

// The frame cameras, ids f00000, f00001, ...; frame i at t0 + i / fps (all of them at once: for
// short paths and tests; `fly` uses PathFrames).
std::vector<Camera> pathFrames(const CameraPath& path, double fps);
std::string frameId(int index);


// Interpolation primitives (exposed for the tests).
// Cubic Hermite between p0 (at s = 0) and p1 (at s = 1) with tangents m0, m1 per unit of s.
glm::dvec3 hermite(const glm::dvec3& p0, const glm::dvec3& m0, const glm::dvec3& p1, const glm::dvec3& m1,
                   double s);
// Rotation between r0 (s = 0) and r1 (s = 1) by quaternion slerp along the shorter arc.
glm::dmat3 slerpRotation(const glm::dmat3& r0, const glm::dmat3& r1, double s);

}  // namespace hv
