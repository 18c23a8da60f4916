#include "hv/layers/layered_texture.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace hv::layers {

PeeledDepthMap peeledDepthMap(const PixelHits& hits, const VisibilityLayers& visibility, int layer) {
  if (layer < 1) throw std::invalid_argument("peeled depth map: layer " + std::to_string(layer) + ", expected >= 1");
  if (visibility.layerOfHit.size() != hits.hits.size() || hits.first.size() != hits.pixelCount() + 1)
    throw std::invalid_argument("peeled depth map: the layers were not peeled from these hit lists");
  PeeledDepthMap d;
  d.layer = layer;
  d.width = hits.width;
  d.height = hits.height;
  d.distance.assign(hits.pixelCount(), std::numeric_limits<float>::infinity());
  for (std::size_t p = 0; p < hits.pixelCount(); ++p)
    for (std::uint32_t i = hits.first[p]; i < hits.first[p + 1]; ++i)
      if (visibility.layerOfHit[i] >= layer) {
        // Hits are nearest first: the first of layers >= k is the nearest.
        d.distance[p] = float(hits.hits[i].depth);
        break;
      }
  return d;
}

bool onPeeledSurface(const LayeredPhotograph& photo, int layer, glm::dvec2 pxDistorted, double distance) {
  if (layer < 1 || layer > int(photo.depthMaps.size())) return false;
  const PeeledDepthMap& d = photo.depthMaps[std::size_t(layer - 1)];
  if (d.width <= 0 || d.height <= 0 || photo.camera.width <= 0 || photo.camera.height <= 0) return false;
  // The texels a bilinear lookup at this point reads (texel centres at i + 0.5).
  const double fx = pxDistorted.x * d.width / photo.camera.width - 0.5;
  const double fy = pxDistorted.y * d.height / photo.camera.height - 0.5;
  const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int dy = 0; dy <= 1; ++dy)
    for (int dx = 0; dx <= 1; ++dx) {
      const int x = std::clamp(x0 + dx, 0, d.width - 1), y = std::clamp(y0 + dy, 0, d.height - 1);
      const double v = d.distance[std::size_t(y) * std::size_t(d.width) + std::size_t(x)];
      if (!std::isfinite(v)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  if (lo > hi) return false;  // no surface of these layers around this ray
  const double tol = photo.tolerance.metres + photo.tolerance.relative * distance;
  return distance >= lo - tol && distance <= hi + tol;
}

namespace {

// GL_LINEAR on the premultiplied texels of a straight-alpha RGBA8 image (clamp to edge).
glm::dvec4 samplePremultiplied(const Image8& img, glm::dvec2 uv) {
  const double fx = uv.x * img.width - 0.5, fy = uv.y * img.height - 0.5;
  const double x0f = std::floor(fx), y0f = std::floor(fy);
  const double tx = fx - x0f, ty = fy - y0f;
  const auto texel = [&](int x, int y) {
    x = std::clamp(x, 0, img.width - 1);
    y = std::clamp(y, 0, img.height - 1);
    const double a = img.channels >= 4 ? img.at(x, y, 3) / 255.0 : 1.0;
    glm::dvec4 v(0.0, 0.0, 0.0, a);
    for (int c = 0; c < 3; ++c) v[c] = a * img.at(x, y, std::min(c, img.channels - 1)) / 255.0;
    return v;
  };
  const int x0 = int(x0f), y0 = int(y0f);
  return glm::mix(glm::mix(texel(x0, y0), texel(x0 + 1, y0), tx),
                  glm::mix(texel(x0, y0 + 1), texel(x0 + 1, y0 + 1), tx), ty);
}

}  // namespace

std::optional<glm::dvec4> layeredTexel(const LayeredPhotograph& photo, const glm::dvec3& worldPoint) {
  const Projection pr = photo.camera.project(worldPoint);
  if (!pr.inFront || !pr.inDistortionDomain) return std::nullopt;
  const double distance = glm::length(worldPoint - photo.camera.center);
  // Visibility-layer order, then the file's order (a stable order of the indices).
  std::vector<std::size_t> order(photo.subImages.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return photo.subImages[a].visibilityLayer < photo.subImages[b].visibilityLayer;
  });
  for (std::size_t i : order) {
    const LayeredSubImage& s = photo.subImages[i];
    const glm::dvec2 px = pr.pxDistorted;
    if (s.rgba.width <= 0 || s.rgba.height <= 0) continue;
    if (px.x < s.window.pxMin.x || px.y < s.window.pxMin.y || px.x > s.window.pxMax.x || px.y > s.window.pxMax.y)
      continue;
    if (!onPeeledSurface(photo, s.visibilityLayer, px, distance)) continue;
    const glm::dvec4 texel = samplePremultiplied(s.rgba, (px - s.window.pxMin) / s.window.size());
    if (texel.a > 0.0) return texel;
  }
  return std::nullopt;
}

}  // namespace hv::layers
