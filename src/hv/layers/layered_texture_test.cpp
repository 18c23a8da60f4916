#include "hv/layers/layered_texture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hv::layers {
namespace {

// A 100 x 100 photograph from the origin looking along +x. An occluder, the plane x = 10, covers
// the left half of the image (pixels x < 50); a façade, the plane x = 20, covers the whole image,
// hidden behind the occluder on the left. Objects: 0 the occluder, 1 the façade.
struct TwoPlanes {
  Camera camera = lookAtCamera("p", glm::dvec3(0.0), glm::dvec3(1.0, 0.0, 0.0), 100, 100, 80.0);

  glm::dvec3 unitRay(glm::dvec2 px) const { return glm::normalize(camera.rayDirection(px)); }
  // The point of plane x = `planeX` seen at pixel `px` (distorted = ideal: no lens).
  glm::dvec3 onPlane(glm::dvec2 px, double planeX) const {
    const glm::dvec3 d = unitRay(px);
    return camera.center + d * ((planeX - camera.center.x) / d.x);
  }
  PixelHits hits() const {
    PixelHits h;
    h.width = camera.width;
    h.height = camera.height;
    for (int y = 0; y < h.height; ++y)
      for (int x = 0; x < h.width; ++x) {
        const glm::dvec2 px(x + 0.5, y + 0.5);
        std::vector<SurfaceHit> s;
        if (x < 50) s.push_back({0, glm::length(onPlane(px, 10.0) - camera.center)});
        s.push_back({1, glm::length(onPlane(px, 20.0) - camera.center)});
        h.appendPixel(s);
      }
    return h;
  }
};

Image8 uniformRgba(int w, int h, glm::u8vec4 c) {
  Image8 img(w, h, 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < 4; ++k) img.at(x, y, k) = c[k];
  return img;
}

TEST(PeeledDepthMap, NearestSurfaceOfTheLayersFromKOn) {
  const TwoPlanes s;
  const PixelHits h = s.hits();
  const VisibilityLayers v = peelVisibilityLayers(h);
  ASSERT_EQ(v.layers.size(), 2u);
  const PeeledDepthMap d1 = peeledDepthMap(h, v, 1), d2 = peeledDepthMap(h, v, 2), d3 = peeledDepthMap(h, v, 3);
  EXPECT_EQ(d1.width, 100);
  EXPECT_EQ(d2.height, 100);
  for (glm::ivec2 p : {glm::ivec2(10, 10), glm::ivec2(49, 70), glm::ivec2(50, 30), glm::ivec2(99, 99)}) {
    const std::size_t i = std::size_t(p.y) * 100 + std::size_t(p.x);
    const glm::dvec2 px(p.x + 0.5, p.y + 0.5);
    const double occluder = glm::length(s.onPlane(px, 10.0)), facade = glm::length(s.onPlane(px, 20.0));
    // Layer 1: whatever is nearest; layer 2: the façade, through the occluder; layer 3: nothing.
    EXPECT_NEAR(d1.distance[i], p.x < 50 ? occluder : facade, 1e-5);
    EXPECT_NEAR(d2.distance[i], facade, 1e-5);
    EXPECT_TRUE(std::isinf(d3.distance[i]));
  }
  EXPECT_THROW(peeledDepthMap(h, v, 0), std::invalid_argument);
  VisibilityLayers wrong = v;
  wrong.layerOfHit.pop_back();
  EXPECT_THROW(peeledDepthMap(h, wrong, 1), std::invalid_argument);
}

TEST(LayeredTexture, EachSubImageOnItsOwnLayersSurfaceOnly) {
  const TwoPlanes s;
  const PixelHits h = s.hits();
  const VisibilityLayers v = peelVisibilityLayers(h);
  LayeredPhotograph photo;
  photo.camera = s.camera;
  // The depth maps at half the photograph's size, as an export at --size 50x50 makes them: the
  // occluder then covers texels x < 25.
  {
    TwoPlanes half;
    half.camera = s.camera.resized(50, 50);
    PixelHits hh;
    hh.width = hh.height = 50;
    for (int y = 0; y < 50; ++y)
      for (int x = 0; x < 50; ++x) {
        const glm::dvec2 px(x + 0.5, y + 0.5);
        std::vector<SurfaceHit> sh;
        if (x < 25) sh.push_back({0, glm::length(half.onPlane(px, 10.0))});
        sh.push_back({1, glm::length(half.onPlane(px, 20.0))});
        hh.appendPixel(sh);
      }
    const VisibilityLayers hv = peelVisibilityLayers(hh);
    photo.depthMaps = {peeledDepthMap(hh, hv, 1), peeledDepthMap(hh, hv, 2)};
  }
  // Layer 1: the photograph, the whole window, half transparent (straight alpha 128). Layer 2 (the
  // painting): window (10, 10)-(90, 90), 8 x 8 texels, green in its top half, transparent below.
  photo.subImages.push_back({1, {{0.0, 0.0}, {100.0, 100.0}}, uniformRgba(4, 4, {200, 100, 50, 128})});
  Image8 paint = uniformRgba(8, 8, {0, 255, 0, 255});
  for (int y = 4; y < 8; ++y)
    for (int x = 0; x < 8; ++x) paint.at(x, y, 3) = 0;
  // Listed before layer 1, as an editor may reorder the stack: the layers' order decides.
  photo.subImages.insert(photo.subImages.begin(), LayeredSubImage{2, {{10.0, 10.0}, {90.0, 90.0}}, paint});

  const double a = 128.0 / 255.0;
  const glm::dvec4 photograph(a * 200.0 / 255.0, a * 100.0 / 255.0, a * 50.0 / 255.0, a);  // premultiplied
  const glm::dvec4 green(0.0, 1.0, 0.0, 1.0);
  const auto expectTexel = [&](const glm::dvec3& P, const std::optional<glm::dvec4>& want, const char* what) {
    const auto got = layeredTexel(photo, P);
    ASSERT_EQ(got.has_value(), want.has_value()) << what;
    if (want)
      for (int c = 0; c < 4; ++c) EXPECT_NEAR((*got)[c], (*want)[c], 1e-12) << what << " channel " << c;
  };
  // (25, 30) in the painting: uv ((25 - 10) / 80, (30 - 10) / 80), texel centres 1.0 and 1.5: green.
  expectTexel(s.onPlane({25.0, 30.0}, 10.0), photograph, "occluder in front of the painted façade");
  expectTexel(s.onPlane({25.0, 30.0}, 20.0), green, "façade hidden by the occluder");
  expectTexel(s.onPlane({75.0, 30.0}, 20.0), photograph, "façade the photograph sees");
  expectTexel(s.onPlane({25.0, 70.0}, 20.0), std::nullopt, "hidden façade where the painting is transparent");
  expectTexel(s.onPlane({5.0, 30.0}, 20.0), std::nullopt, "hidden façade outside the painting's window");
  expectTexel(s.onPlane({25.0, 30.0}, 15.0), std::nullopt, "between the occluder and the façade");
  expectTexel(glm::dvec3(-5.0, 0.0, 0.0), std::nullopt, "behind the camera");
  // The tolerance: the range of the four texels a bilinear lookup at (25, 30) reads (half-size
  // texels 12, 13 by 14, 15, centred on full-size pixels 25, 27 by 29, 31), widened by 5 cm + 0.2 %
  // of the distance.
  double lo = 1e9, hi = 0.0;
  for (double x : {25.0, 27.0})
    for (double y : {29.0, 31.0}) {
      lo = std::min(lo, glm::length(s.onPlane({x, y}, 20.0)));
      hi = std::max(hi, glm::length(s.onPlane({x, y}, 20.0)));
    }
  ASSERT_GT(hi - lo, 0.01);  // the façade is seen obliquely: the range matters
  const glm::dvec3 ray = s.unitRay({25.0, 30.0});
  const auto tol = [](double d) { return 0.05 + 2e-3 * d; };
  expectTexel(ray * (hi + tol(hi) - 0.005), green, "just within the tolerance behind the façade");
  expectTexel(ray * (hi + tol(hi) + 0.005), std::nullopt, "just beyond the tolerance behind the façade");
  expectTexel(ray * (lo - tol(lo) + 0.005), green, "just within the tolerance in front of the façade");
  expectTexel(ray * (lo - tol(lo) - 0.005), std::nullopt, "just beyond the tolerance in front of the façade");
  // At the occluder's edge (texels 24 | 25 of the half-size maps: pixels 48..50), a point of the
  // façade reads both surfaces around it: the range holds it.
  EXPECT_TRUE(onPeeledSurface(photo, 1, {49.5, 30.0}, glm::length(s.onPlane({49.5, 30.0}, 20.0))));
  EXPECT_FALSE(onPeeledSurface(photo, 1, {45.0, 30.0}, glm::length(s.onPlane({45.0, 30.0}, 20.0))));
  EXPECT_FALSE(onPeeledSurface(photo, 3, {45.0, 30.0}, 20.0)) << "no such layer";
}

}  // namespace
}  // namespace hv::layers
