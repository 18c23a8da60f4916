#include "hv/viewer/then_now.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hv::viewer {

PixelRect photoRectInWindow(glm::ivec2 photoSize, glm::ivec2 windowSize) {
  if (photoSize.x <= 0 || photoSize.y <= 0 || windowSize.x <= 0 || windowSize.y <= 0) return {};
  const glm::dvec2 photo(photoSize), window(windowSize);
  const double s = std::min(window.x / photo.x, window.y / photo.y);
  const glm::dvec2 offset = (window - photo * s) / 2.0;
  return {offset, offset + photo * s};
}

double quantizedAlpha(double alpha) {
  return std::round(std::clamp(std::isfinite(alpha) ? alpha : 0.0, 0.0, 1.0) * 255.0) / 255.0;
}

std::optional<OverlayQuad> thenNowQuad(glm::ivec2 photoSize, glm::ivec2 windowSize, const ThenNowSettings& s) {
  const PixelRect rect = photoRectInWindow(photoSize, windowSize);
  if (rect.hi.x <= rect.lo.x || rect.hi.y <= rect.lo.y) return std::nullopt;
  OverlayQuad q;
  q.window = rect;
  q.uv = {{0.0, 0.0}, {1.0, 1.0}};
  if (s.mode == ThenNowMode::Opacity) {
    q.alpha = quantizedAlpha(s.opacity);
    if (q.alpha <= 0.0) return std::nullopt;
    return q;
  }
  const double t = std::clamp(std::isfinite(s.swipe) ? s.swipe : 0.0, 0.0, 1.0);
  if (t <= 0.0) return std::nullopt;
  q.window.hi.x = rect.lo.x + t * (rect.hi.x - rect.lo.x);
  q.uv.hi.x = t;
  q.alpha = 1.0;
  return q;
}

Image8 compositeThenNow(const Image8& render, const Image8& photo, const ThenNowSettings& s) {
  if (render.channels < 3 || photo.channels < 3)
    throw std::invalid_argument("compositeThenNow: the render and the photograph must be RGB or RGBA");
  Image8 out = render;
  const std::optional<OverlayQuad> q = thenNowQuad({photo.width, photo.height}, {render.width, render.height}, s);
  if (!q) return out;
  const glm::dvec2 size = q->window.hi - q->window.lo;
  const glm::dvec2 uvSize = q->uv.hi - q->uv.lo;
  for (int y = 0; y < render.height; ++y)
    for (int x = 0; x < render.width; ++x) {
      const glm::dvec2 centre(x + 0.5, y + 0.5);
      if (centre.x < q->window.lo.x || centre.x >= q->window.hi.x || centre.y < q->window.lo.y ||
          centre.y >= q->window.hi.y)
        continue;
      const glm::dvec2 uv = q->uv.lo + (centre - q->window.lo) / size * uvSize;
      const int px = std::clamp(int(std::floor(uv.x * photo.width)), 0, photo.width - 1);
      const int py = std::clamp(int(std::floor(uv.y * photo.height)), 0, photo.height - 1);
      for (int c = 0; c < 3; ++c) {
        const double v = q->alpha * photo.at(px, py, c) + (1.0 - q->alpha) * render.at(x, y, c);
        out.at(x, y, c) = std::uint8_t(std::clamp(std::lround(v), 0L, 255L));
      }
    }
  return out;
}

}  // namespace hv::viewer
