// "Then and now": at a photograph's camera, the photograph laid over the render of today's
// geometry without it (leave-one-out), either faded (an opacity) or split by a vertical swipe
// line (the photograph left of it). This is the layout and the blend as plain arithmetic; the
// viewer draws the quad as a textured, alpha-blended rectangle (Dear ImGui's image), and
// compositeThenNow is the CPU reference of that drawing.
//
// Conventions: window pixels as hv/camera/camera.h (origin at the top-left corner, pixel (x, y)
// covers [x, x + 1) x [y, y + 1), centre at + 0.5); texture coordinates in [0, 1], (0, 0) the
// photograph's top-left corner.
#pragma once

#include "hv/image/image.h"

#include <glm/glm.hpp>

#include <optional>

namespace hv::viewer {

enum class ThenNowMode { Opacity, Swipe };

struct ThenNowSettings {
  ThenNowMode mode = ThenNowMode::Opacity;
  double opacity = 1.0;  // Opacity: the photograph's weight, 0 (the render) .. 1 (the photograph)
  double swipe = 0.5;    // Swipe: the line's position across the photograph, 0 (left edge) .. 1 (right)
};

struct PixelRect {
  glm::dvec2 lo{0.0}, hi{0.0};
  bool operator==(const PixelRect&) const = default;
};

// Where a photograph of `photoSize` pixels lies in a window of `windowSize` when the view is its
// camera fitted to the window (navigation.h: the camera itself when the aspect ratios agree, else
// photoInWindow's letterbox): scaled by min(W / w, H / h) and centred.
PixelRect photoRectInWindow(glm::ivec2 photoSize, glm::ivec2 windowSize);

// The photograph's rectangle to draw over the render: where in the window, which part of the
// photograph (texture coordinates), and with what alpha (the blend is
// alpha * photograph + (1 - alpha) * render). None when nothing of the photograph shows (opacity
// 0, swipe at the left edge).
struct OverlayQuad {
  PixelRect window;
  PixelRect uv;
  double alpha = 1.0;
};
std::optional<OverlayQuad> thenNowQuad(glm::ivec2 photoSize, glm::ivec2 windowSize, const ThenNowSettings& s);

// The alpha as an 8-bit vertex colour carries it (round(alpha * 255) / 255), which the drawing uses.
double quantizedAlpha(double alpha);

// The CPU reference of the overlay drawn over `render` (RGB or RGBA, the window's size): each pixel
// whose centre lies in the quad takes the photograph's texel nearest the centre's texture
// coordinate, blended with the quantized alpha and rounded; the others keep the render. `photo`
// RGB or RGBA (its alpha ignored: a photograph is opaque).
Image8 compositeThenNow(const Image8& render, const Image8& photo, const ThenNowSettings& s);

}  // namespace hv::viewer
