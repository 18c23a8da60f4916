#include "hv/camera/camera_path.h"

#include "hv/io/cameras_json.h"

#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

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
  const double n = std::floor((path.endTime() - path.startTime()) * fps + 1e-9) + 1.0;
  if (n > 1e7)
    throw std::invalid_argument("the path would have " + std::to_string(n) + " frames (more than 10^7)");
  return int(n);
}

std::vector<Camera> pathFrames(const CameraPath& path, double fps) {
  const int n = pathFrameCount(path, fps);
  std::vector<Camera> frames;
  frames.reserve(size_t(n));
  for (int i = 0; i < n; ++i) {
    // t0 + i / fps rather than accumulating 1/fps, so rounding does not drift along the path.
    frames.push_back(path.at(std::min(path.startTime() + i / fps, path.endTime())));
    frames.back().id = frameId(i);
  }
  return frames;
}

CameraPath parseCameraPath(const std::string& text, const std::string& file, Diagnostics& diag) {
  CameraFileOptions opts;
  opts.requireImages = false;
  opts.checkImageFiles = false;
  const std::string dir = std::filesystem::path(file).parent_path().string();
  Diagnostics local;
  std::vector<Photo> photos = parseCameraJson(text, file, dir.empty() ? "." : dir, opts, local);
  diag.warnings.insert(diag.warnings.end(), local.warnings.begin(), local.warnings.end());
  if (!local.ok())
    throw InputError(
        local.errors.front() +
        (local.errors.size() > 1 ? " (and " + std::to_string(local.errors.size() - 1) + " more)" : "") +
        "; every key camera of a path must be readable");
  // parseCameraJson has already parsed and checked the document: every camera loaded, in order.
  const nlohmann::json doc = nlohmann::json::parse(text);
  const nlohmann::json& cams = doc.at("cameras");
  std::vector<PathKey> keys;
  for (size_t i = 0; i < photos.size(); ++i) {
    PathKey k;
    k.camera = std::move(photos[i].camera);
    const nlohmann::json& j = cams.at(i);
    if (j.contains("t") && !j["t"].is_null()) {
      if (!j["t"].is_number())
        throw InputError(file + ": camera '" + k.camera.id + "': t: expected a number of seconds, got " +
                         j["t"].dump().substr(0, 40));
      k.time = j["t"].get<double>();
    } else {
      k.time = keys.empty() ? 0.0 : keys.back().time + 1.0;
    }
    keys.push_back(std::move(k));
  }
  try {
    return CameraPath(std::move(keys));
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  }
}

CameraPath readCameraPath(const std::string& path, Diagnostics& diag) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open camera path file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parseCameraPath(ss.str(), path, diag);
}

}  // namespace hv
