#include "hv/camera/camera_path.h"


#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

namespace hv {

namespace {

std::string keyName(const PathKey& k, size_t index) {
  return k.camera.id.empty() ? "key #" + std::to_string(index) : "camera '" + k.camera.id + "'";
}

// Catmull-Rom tangent at key i (per second), the end points duplicated (see the header).
glm::dvec3 tangent(const std::vector<PathKey>& k, size_t i) {
  const size_t prev = i == 0 ? 0 : i - 1;
  const size_t next = std::min(i + 1, k.size() - 1);
  if (prev == next) return glm::dvec3(0.0);
  return (k[next].camera.center - k[prev].camera.center) / (k[next].time - k[prev].time);
}

}  // namespace

glm::dvec3 hermite(const glm::dvec3& p0, const glm::dvec3& m0, const glm::dvec3& p1, const glm::dvec3& m1,
                   double s) {
  // Cubic Hermite basis functions (e.g. Wikipedia "Cubic Hermite spline", unit interval).
  const double s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  return h00 * p0 + h10 * m0 + h01 * p1 + h11 * m1;
}

glm::dmat3 slerpRotation(const glm::dmat3& r0, const glm::dmat3& r1, double s) {
  const glm::dquat q0 = glm::normalize(glm::quat_cast(r0));
  glm::dquat q1 = glm::normalize(glm::quat_cast(r1));
  // q and -q are the same rotation; taking the one nearer q0 makes slerp follow the shorter arc.
  if (glm::dot(q0, q1) < 0.0) q1 = -q1;
  // glm::slerp falls back to a linear blend when the quaternions are nearly equal, so renormalise
  // before building the matrix: a unit quaternion gives an orthonormal matrix up to rounding.
  return glm::mat3_cast(glm::normalize(glm::slerp(q0, q1, s)));
}

CameraPath::CameraPath(std::vector<PathKey> keys) : keys_(std::move(keys)) {
  if (keys_.empty()) throw InputError("a camera path needs at least one key camera");
  const Camera& first = keys_.front().camera;
  for (size_t i = 0; i < keys_.size(); ++i) {
    const PathKey& k = keys_[i];
    if (!std::isfinite(k.time)) throw InputError(keyName(k, i) + ": t: expected a finite number of seconds");
    if (i > 0 && !(k.time > keys_[i - 1].time))
      throw InputError(keyName(k, i) + ": t: expected a time after the previous key's (" +
                       std::to_string(keys_[i - 1].time) + " s), got " + std::to_string(k.time) + " s");
    if (k.camera.width != first.width || k.camera.height != first.height)
      throw InputError(keyName(k, i) + ": width, height: " + std::to_string(k.camera.width) + "x" +
                       std::to_string(k.camera.height) + " differs from the first key's " +
                       std::to_string(first.width) + "x" + std::to_string(first.height) +
                       " (the frames of a path share one size)");
    // A quaternion represents proper rotations only.
    if (glm::determinant(k.camera.camFromWorld) < 0.0)
      throw InputError(keyName(k, i) + ": rotation: expected a rotation (det = +1), got a reflection");
  }
}

size_t CameraPath::segment(double t) const {
  if (keys_.size() < 2) return 0;
  // First key strictly after t, minus one: t_i <= t < t_i+1; the last segment also takes t_end.
  const auto it =
      std::upper_bound(keys_.begin(), keys_.end(), t, [](double v, const PathKey& k) { return v < k.time; });
  const size_t i = it == keys_.begin() ? 0 : size_t(it - keys_.begin()) - 1;
  return std::min(i, keys_.size() - 2);
}

glm::dvec3 CameraPath::position(double t) const {
  if (keys_.size() == 1) return keys_.front().camera.center;
  t = std::clamp(t, startTime(), endTime());
  const size_t i = segment(t);
  const double dt = keys_[i + 1].time - keys_[i].time;
  const double s = (t - keys_[i].time) / dt;
  // Tangents per second, scaled to per unit of s.
  return hermite(keys_[i].camera.center, dt * tangent(keys_, i), keys_[i + 1].camera.center,
                 dt * tangent(keys_, i + 1), s);
}

Camera CameraPath::at(double t) const {
  if (keys_.size() == 1) {
    Camera c = keys_.front().camera;
    c.id.clear();
    return c;
  }
  t = std::clamp(t, startTime(), endTime());
  const size_t i = segment(t);
  const Camera& a = keys_[i].camera;
  const Camera& b = keys_[i + 1].camera;
  const double s = (t - keys_[i].time) / (keys_[i + 1].time - keys_[i].time);
  Camera c = s < 1.0 ? a : b;  // size, distortion: the earlier key's (the later one's at its own time)
  c.id.clear();
  c.center = position(t);
  c.camFromWorld = slerpRotation(a.camFromWorld, b.camFromWorld, s);
  c.focal = glm::mix(a.focal, b.focal, s);
  c.principal = glm::mix(a.principal, b.principal, s);
  c.skew = a.skew + (b.skew - a.skew) * s;
  return c;
}

std::string frameId(int index) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "f%05d", index);
  return buf;
}

int pathFrameCount(const CameraPath& path, double fps) {
  if (!(fps > 0.0) || !std::isfinite(fps)) throw std::invalid_argument("fps: expected a positive number");
  const double seconds = path.endTime() - path.startTime();
  const double n = std::floor(seconds * fps + 1e-9) + 1.0;
  if (!(n <= double(kMaxPathFrames))) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "the path would have %.4g frames (%.6g s at %.6g fps), more than the limit of %d; lower --fps "
                  "or the keys' times",
                  n, seconds, fps, kMaxPathFrames);
    throw std::invalid_argument(text);
  }
  return int(n);
}

PathFrames::PathFrames(CameraPath path, double fps)
    : path_(std::move(path)), fps_(fps), count_(pathFrameCount(path_, fps)) {}

Camera PathFrames::operator[](int index) const {
  // t0 + i / fps rather than accumulating 1/fps, so rounding does not drift along the path.
  Camera c = path_.at(std::min(path_.startTime() + index / fps_, path_.endTime()));
  c.id = frameId(index);
  return c;
}

std::vector<Camera> pathFrames(const CameraPath& path, double fps) {
  const PathFrames lazy(path, fps);
  std::vector<Camera> frames;
  frames.reserve(size_t(lazy.size()));
  for (int i = 0; i < lazy.size(); ++i) frames.push_back(lazy[i]);
  return frames;
}

}  // namespace hv
