#include "hv/viewer/tour.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace hv::viewer {

double pathLength(const std::vector<glm::dvec3>& centres, const std::vector<int>& order) {
  double length = 0.0;
  for (size_t i = 1; i < order.size(); ++i)
    length += glm::length(centres[size_t(order[i])] - centres[size_t(order[i - 1])]);
  return length;
}

std::vector<int> tourOrder(const std::vector<glm::dvec3>& centres, int maxPasses) {
  std::vector<int> order = streetOrder(centres);
  const size_t n = order.size();
  if (n < 3) return order;
  auto d = [&](size_t a, size_t b) { return glm::length(centres[size_t(order[a])] - centres[size_t(order[b])]); };
  // Reversing order[i..j] replaces the edges (i-1, i) and (j, j+1) by (i-1, j) and (i, j+1); at
  // an end of the open path the missing edge costs nothing.
  for (int pass = 0; pass < maxPasses; ++pass) {
    bool improved = false;
    for (size_t i = 0; i + 1 < n; ++i)
      for (size_t j = i + 1; j < n; ++j) {
        if (i == 0 && j == n - 1) continue;  // reversing everything changes nothing
        const double before = (i > 0 ? d(i - 1, i) : 0.0) + (j + 1 < n ? d(j, j + 1) : 0.0);
        const double after = (i > 0 ? d(i - 1, j) : 0.0) + (j + 1 < n ? d(i, j + 1) : 0.0);
        if (after < before - 1e-12 * (1.0 + before)) {
          std::reverse(order.begin() + long(i), order.begin() + long(j) + 1);
          improved = true;
        }
      }
    if (!improved) break;
  }
  return order;
}

std::vector<PathKey> focusContextKeys(const std::vector<Camera>& photos, int width, int height, const TourSettings& s) {
  if (photos.empty()) throw std::invalid_argument("a tour needs at least one photograph");
  if (width <= 0 || height <= 0) throw std::invalid_argument("a tour needs a positive image size");
  std::vector<PathKey> keys;
  double t = 0.0;
  const double minStep = 1e-3;  // keys strictly increase in time
  for (size_t i = 0; i < photos.size(); ++i) {
    Camera window = photos[i];
    window.width = width;
    window.height = height;
    // FocusContextPath from the photograph itself gives its focus and context views at the window size.
    const FocusContextPath fc(window, photos[i], s.focus);
    if (!keys.empty()) {
      const double distance = glm::length(fc.focus().center - keys.back().camera.center);
      t += std::max({s.focus.travelSeconds, distance / std::max(s.speed, 1e-9), minStep});
    }
    keys.push_back({fc.focus(), t});
    if (s.focus.holdSeconds > 0.0) {
      t += s.focus.holdSeconds;
      keys.push_back({fc.focus(), t});
    }
    if (s.focus.stepBack > 0.0 || s.focus.zoomOut != 1.0) {
      t += std::max(s.focus.backSeconds, minStep);
      keys.push_back({fc.context(), t});
    }
  }
  for (size_t i = 0; i < keys.size(); ++i) keys[i].camera.id = frameId(int(i));
  return keys;
}

std::vector<PathKey> orbitKeys(const glm::dvec3& around, const glm::dvec3& up, int width, int height,
                               const OrbitSettings& s) {
  if (!(s.radius > 0.0) || !std::isfinite(s.radius))
    throw std::invalid_argument("orbit: the radius must be a positive distance, got " + std::to_string(s.radius));
  if (!(s.seconds > 0.0) || s.keys < 3)
    throw std::invalid_argument("orbit: a turn needs a positive time and at least 3 keys");
  if (!(std::abs(s.elevationDeg) < 89.0))
    throw std::invalid_argument("orbit: the elevation must be within (-89, 89) degrees");
  if (width <= 0 || height <= 0) throw std::invalid_argument("orbit: the image size must be positive");
  const UpFrame f = upFrame(up);
  const double height_ = s.radius * std::tan(s.elevationDeg * std::numbers::pi / 180.0);
  const double focal = width / 2.0 / std::tan(s.fovDeg * std::numbers::pi / 360.0);
  std::vector<PathKey> keys;
  for (int k = 0; k <= s.keys; ++k) {
    const double a = 2.0 * std::numbers::pi * k / s.keys;
    const glm::dvec3 eye = around + s.radius * (std::cos(a) * f.east + std::sin(a) * f.north) + height_ * f.up;
    keys.push_back({lookAtCamera(frameId(k), eye, around, width, height, focal, f.up), s.seconds * k / s.keys});
  }
  return keys;
}

}  // namespace hv::viewer
