#include "hv/viewer/navigation.h"

#include "hv/camera/camera_path.h"
#include "hv/scene/ray_query.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace hv::viewer {

UpFrame upFrame(const glm::dvec3& up) {
  UpFrame f;
  f.up = glm::normalize(up);
  // Any horizontal axis will do for east; the world x axis unless up is (nearly) along it.
  const glm::dvec3 seed = std::abs(f.up.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  f.east = glm::normalize(seed - glm::dot(seed, f.up) * f.up);
  f.north = glm::cross(f.up, f.east);
  return f;
}

Heading headingOf(const glm::dvec3& forward, const UpFrame& f) {
  const glm::dvec3 d = glm::normalize(forward);
  Heading h;
  h.yaw = std::atan2(glm::dot(d, f.north), glm::dot(d, f.east));
  h.pitch = std::asin(std::clamp(glm::dot(d, f.up), -1.0, 1.0));
  return h;
}

glm::dvec3 forwardOf(const Heading& h, const UpFrame& f) {
  return std::cos(h.pitch) * (std::cos(h.yaw) * f.east + std::sin(h.yaw) * f.north) + std::sin(h.pitch) * f.up;
}

glm::dmat3 camFromWorldLooking(const glm::dvec3& forward, const glm::dvec3& up) {
  const glm::dvec3 z = glm::normalize(forward);
  const glm::dvec3 x = glm::normalize(glm::cross(z, up));
  const glm::dvec3 y = glm::cross(z, x);  // image down
  return glm::transpose(glm::dmat3(x, y, z));  // rows: the camera axes in the world
}

glm::dvec3 forwardOf(const Camera& c) { return glm::transpose(c.camFromWorld) * glm::dvec3(0, 0, 1); }

Navigator::Navigator(const glm::dvec3& up, const RayQuery* geometry, NavigationSettings s)
    : frame_(upFrame(up)), geometry_(geometry), settings_(s) {}

void Navigator::setCamera(const Camera& camera) {
  camera_ = camera;
  heading_ = headingOf(forwardOf(camera), frame_);
  haveTarget_ = false;
}

void Navigator::setMode(Mode m) {
  mode_ = m;
  haveTarget_ = false;
}

bool Navigator::groundBelow(const glm::dvec3& eye, glm::dvec3& ground) const {
  if (!geometry_) return false;
  const glm::dvec3 probe = eye - frame_.up * (settings_.eyeHeight - settings_.maxStep);
  const auto hit = geometry_->intersect(probe, -frame_.up);
  if (!hit) return false;
  ground = hit->position;
  return true;
}

// Shortens a horizontal step so the body stays bodyRadius away from what it would walk into,
// tested at knee (just above maxStep) and eye level.
glm::dvec3 Navigator::walkStep(const glm::dvec3& from, const glm::dvec3& step) const {
  const double len = glm::length(step);
  if (!geometry_ || len <= 0.0) return step;
  const glm::dvec3 dir = step / len;
  double allowed = len;
  const double knee = settings_.eyeHeight - settings_.maxStep - 0.05 * settings_.eyeHeight;
  for (const double below : {0.0, std::max(0.0, knee)}) {
    const auto hit = geometry_->intersect(from - frame_.up * below, dir, 0.0, len + settings_.bodyRadius);
    if (hit) allowed = std::min(allowed, std::max(0.0, hit->t - settings_.bodyRadius));
  }
  return dir * allowed;
}

bool Navigator::update(const NavigationInput& in) {
  const Camera before = camera_;
  const NavigationSettings& s = settings_;
  if (in.lookPixels != glm::dvec2(0.0)) {
    heading_.yaw -= in.lookPixels.x * s.lookRadiansPerPixel;  // mouse right turns right (clockwise seen from above)
    heading_.pitch = std::clamp(heading_.pitch - in.lookPixels.y * s.lookRadiansPerPixel, -s.maxPitch, s.maxPitch);
    camera_.camFromWorld = camFromWorldLooking(forwardOf(heading_, frame_), frame_.up);
  }
  const glm::dmat3 worldFromCam = glm::transpose(camera_.camFromWorld);
  const glm::dvec3 right = worldFromCam[0], forward = worldFromCam[2];
  const double speed = s.speed * (in.fast ? s.fastFactor : 1.0);
  glm::dvec3 move = in.move;
  if (glm::length(move) > 1.0) move = glm::normalize(move);  // diagonals are not faster
  if (mode_ == Mode::Fly) {
    camera_.center += (right * move.x + forward * move.y + frame_.up * move.z) * (speed * in.dt);
  } else {
    // Walking: horizontal moves only; the ground decides the height.
    auto horizontal = [&](glm::dvec3 v) { return v - glm::dot(v, frame_.up) * frame_.up; };
    glm::dvec3 f = horizontal(forward);
    f = glm::length(f) > 1e-9 ? glm::normalize(f) : forwardOf(Heading{heading_.yaw, 0.0}, frame_);
    const glm::dvec3 r = glm::normalize(horizontal(right));
    const glm::dvec3 step = (r * move.x + f * move.y) * (speed * in.dt);
    camera_.center += walkStep(camera_.center, step);
    glm::dvec3 ground;
    if (groundBelow(camera_.center, ground)) {
      eyeTarget_ = glm::dot(ground, frame_.up) + s.eyeHeight;
      haveTarget_ = true;
    }
    if (haveTarget_) {
      const double h = glm::dot(camera_.center, frame_.up);
      // Exponential approach: frame-rate independent (the same after one 1/30 s step as after two 1/60 s ones).
      const double a = s.heightSmoothingSeconds > 0.0 ? 1.0 - std::exp(-in.dt / s.heightSmoothingSeconds) : 1.0;
      camera_.center += frame_.up * ((eyeTarget_ - h) * a);
    }
  }
  return camera_.center != before.center || camera_.camFromWorld != before.camFromWorld;
}

Camera photoInWindow(const Camera& photo, int width, int height) {
  Camera c = photo;
  const double s = std::min(double(width) / photo.width, double(height) / photo.height);
  const glm::dvec2 offset((width - photo.width * s) / 2.0, (height - photo.height * s) / 2.0);
  c.width = width;
  c.height = height;
  c.focal = photo.focal * s;
  c.principal = photo.principal * s + offset;
  c.skew = photo.skew * s;
  c.distortion.reset();
  return c;
}

ScaleDefaults scaleDefaults(double scale) {
  ScaleDefaults d;
  if (!(scale > 0.0) || !std::isfinite(scale)) return d;
  d.speed = scale / 2.0;
  d.stepBack = scale;
  d.orbitRadius = 2.0 * scale;
  return d;
}

double rollOf(const Camera& c, const glm::dvec3& up) {
  const glm::dmat3 worldFromCam = glm::transpose(c.camFromWorld);
  const glm::dvec3 x = worldFromCam[0], y = worldFromCam[1];
  const double right = glm::dot(x, up), upward = -glm::dot(y, up);
  if (std::abs(right) + std::abs(upward) < 1e-12) return 0.0;
  return std::atan2(right, upward);
}

Camera levelled(const Camera& c, const glm::dvec3& up) {
  const glm::dvec3 forward = forwardOf(c), u = glm::normalize(up);
  if (glm::length(glm::cross(glm::normalize(forward), u)) < 1e-9) return c;
  Camera out = c;
  out.camFromWorld = camFromWorldLooking(forward, u);
  return out;
}

double smoothstep01(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s * s * (3.0 - 2.0 * s);
}

Camera blendCameras(const Camera& a, const Camera& b, double s) {
  Camera c = a;
  c.center = glm::mix(a.center, b.center, s);
  c.camFromWorld = slerpRotation(a.camFromWorld, b.camFromWorld, s);
  c.focal = glm::mix(a.focal, b.focal, s);
  c.principal = glm::mix(a.principal, b.principal, s);
  c.skew = a.skew + (b.skew - a.skew) * s;
  c.distortion.reset();
  return c;
}

FocusContextPath::FocusContextPath(const Camera& from, const Camera& photo, const FocusContextSettings& s,
                                   const RayQuery* geometry)
    : from_(from), s_(s) {
  from_.distortion.reset();
  focus_ = photoInWindow(photo, from.width, from.height);
  focus_.id = photo.id;
  if (s.levelHorizon && std::abs(rollOf(focus_, s.up)) > s.maxKeptRollDeg * std::numbers::pi / 180.0)
    focus_ = levelled(focus_, s.up);
  double back = std::max(0.0, s.stepBack);
  const glm::dvec3 forward = forwardOf(focus_);
  if (geometry && back > 0.0) {
    // Stepping back must not put a wall between the camera and the photograph.
    if (const auto hit = geometry->intersect(focus_.center, -forward, 0.0, back + s.clearance))
      back = std::max(0.0, hit->t - s.clearance);
  }
  context_ = focus_;
  context_.center = focus_.center - forward * back;
  context_.focal = focus_.focal * s.zoomOut;
  const glm::dvec2 mid(focus_.width / 2.0, focus_.height / 2.0);
  context_.principal = mid + (focus_.principal - mid) * s.zoomOut;
}

double FocusContextPath::duration() const { return s_.travelSeconds + s_.holdSeconds + s_.backSeconds; }

Camera FocusContextPath::at(double t) const {
  if (t < s_.travelSeconds) return blendCameras(from_, focus_, smoothstep01(t / s_.travelSeconds));
  t -= s_.travelSeconds;
  if (t < s_.holdSeconds) return focus_;
  t -= s_.holdSeconds;
  if (s_.backSeconds <= 0.0 || t >= s_.backSeconds) return context_;
  return blendCameras(focus_, context_, smoothstep01(t / s_.backSeconds));
}

int nearestCentre(const std::vector<glm::dvec3>& centres, const glm::dvec3& p) {
  int best = -1;
  double bestD = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < centres.size(); ++i) {
    const double d = glm::length(centres[i] - p);
    if (d < bestD) {
      bestD = d;
      best = int(i);
    }
  }
  return best;
}

std::vector<int> streetOrder(const std::vector<glm::dvec3>& centres) {
  std::vector<int> order;
  if (centres.empty()) return order;
  glm::dvec3 centroid(0.0);
  for (const auto& c : centres) centroid += c;
  centroid /= double(centres.size());
  int current = 0;
  for (size_t i = 1; i < centres.size(); ++i)
    if (glm::length(centres[i] - centroid) > glm::length(centres[size_t(current)] - centroid)) current = int(i);
  std::vector<bool> visited(centres.size(), false);
  for (;;) {
    order.push_back(current);
    visited[size_t(current)] = true;
    int next = -1;
    double bestD = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < centres.size(); ++i) {
      if (visited[i]) continue;
      const double d = glm::length(centres[i] - centres[size_t(current)]);
      if (d < bestD) {
        bestD = d;
        next = int(i);
      }
    }
    if (next < 0) break;
    current = next;
  }
  return order;
}

int stepAlong(const std::vector<int>& order, int current, int steps) {
  if (order.empty()) return -1;
  const auto it = std::find(order.begin(), order.end(), current);
  if (it == order.end()) return steps >= 0 ? order.front() : order.back();
  const long pos = std::clamp(long(it - order.begin()) + steps, 0L, long(order.size()) - 1);
  return order[size_t(pos)];
}

}  // namespace hv::viewer
