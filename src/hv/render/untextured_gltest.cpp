// Where no photograph contributes, on llvmpipe: the shaded surfaces and the sky of
// shaders/untextured.glsl against their CPU twins (render/untextured.h) at sampled pixels, with the
// surface normals and the sky directions from an exact ray cast, not from the GL depth; coverage
// (alpha) stays 0 there.
#include "hv/render/renderer.h"

#include "hv/image/native/png_write.h"
#include "hv/render/testing/gl_test_support.h"
#include "hv/render/untextured.h"
#include "hv/scene/native/raycast.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv::render {
namespace {

using testing::kStreetOrigin;

class UntexturedGlTest : public testing::GlTest {};

glm::dvec3 pixelColour(const Image8& img, int x, int y) {
  return glm::dvec3(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)) / 255.0;
}

// What the pixel's centre ray sees, by ray casting the scene's geometry: the facing normal of the
// surface, or nothing (sky). `robust` is false near an edge, where the ±1.5 px neighbour rays
// see another surface or none: there the shader's screen-space normal (dFdx/dFdy of the rebuilt
// point) mixes two surfaces, and rasterisation and the ray cast may disagree on coverage.
struct Seen {
  std::optional<glm::dvec3> normal;
  glm::dvec3 direction;
  bool robust = true;
};

Seen castPixel(const RayCaster& caster, const Camera& view, int x, int y) {
  auto normalAt = [&](glm::dvec2 px) -> std::optional<glm::dvec3> {
    const glm::dvec3 dir = view.rayDirection(px);
    const auto hit = caster.intersect(view.center, dir, 0.0, 1e9);
    if (!hit) return std::nullopt;
    return glm::dot(hit->normal, dir) > 0.0 ? -hit->normal : hit->normal;
  };
  Seen s;
  const glm::dvec2 c(x + 0.5, y + 0.5);
  s.direction = view.rayDirection(c);
  s.normal = normalAt(c);
  for (glm::dvec2 off : {glm::dvec2(1.5, 0), glm::dvec2(-1.5, 0), glm::dvec2(0, 1.5), glm::dvec2(0, -1.5)}) {
    const auto n = normalAt(c + off);
    if (n.has_value() != s.normal.has_value() || (n && glm::dot(*n, *s.normal) < 0.999)) s.robust = false;
  }
  return s;
}

Mesh allGeometry(const Scene& scene) {
  Mesh all = scene.terrain;
  all.append(scene.buildings);
  return all;
}

TEST_F(UntexturedGlTest, SurfacesAreShadedAndTheSkyMatchesTheCpuTwin) {
  const Scene scene = testing::streetScene();  // no photographs
  const glm::dvec3 o = kStreetOrigin;
  Diagnostics diag;
  RenderSettings settings;
  settings.blend.k = 1;  // at most one photograph here
  settings.depthSize = 256;
  Renderer renderer(scene, settings, diag);
  const Camera view = testing::lookAt("v", o + glm::dvec3(8, -11, 2.2), o + glm::dvec3(-3, 31, 12), 160, 120, 110);
  const RenderOutput out = renderer.render(view);
  ASSERT_EQ(out.rgba.width, 160);
  const RayCaster caster(allGeometry(scene));

  int surfaces = 0, sky = 0, notRobust = 0;
  double maxSurfaceErr = 0.0, maxSkyErr = 0.0;
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      // Nothing is covered: no photograph contributes anywhere.
      ASSERT_EQ(out.rgba.at(x, y, 3), 0) << x << "," << y;
      if (x % 3 || y % 3) continue;
      const Seen seen = castPixel(caster, view, x, y);
      if (!seen.robust) {
        ++notRobust;
        continue;
      }
      const glm::dvec3 got = pixelColour(out.rgba, x, y);
      const glm::dvec3 want = seen.normal ? shadeUntextured(*seen.normal, scene.up, settings.untextured)
                                          : skyColor(seen.direction, scene.up, settings.untextured);
      const double err = glm::length(got - want) / std::sqrt(3.0) * 255.0;  // RMS over channels, in 8-bit steps
      // Tolerance: 8-bit rounding (half a step) plus the float shader's normal, rebuilt from the
      // view depth's finite differences (the ray cast's normal is exact): 1.5 steps (llvmpipe: 0.5).
      EXPECT_LT(err, 1.5) << (seen.normal ? "surface" : "sky") << " pixel " << x << "," << y << ": got " << got.r * 255
                          << "," << got.g * 255 << "," << got.b * 255 << " want " << want.r * 255 << "," << want.g * 255
                          << "," << want.b * 255;
      (seen.normal ? maxSurfaceErr : maxSkyErr) = std::max(seen.normal ? maxSurfaceErr : maxSkyErr, err);
      ++(seen.normal ? surfaces : sky);
      if (seen.normal) {
        // Neither the background colour (black) nor black: the geometry shows.
        EXPECT_GT(std::min({got.r, got.g, got.b}), 0.1) << x << "," << y;
      }
    }
  std::cout << "[ untextured ] " << surfaces << " surface and " << sky << " sky pixels compared (" << notRobust
            << " near edges skipped); largest error " << maxSurfaceErr << " / " << maxSkyErr << " steps\n";
  // The view shows ground, both buildings' walls and sky: the comparison is not vacuous.
  EXPECT_GT(surfaces, 500);
  EXPECT_GT(sky, 100);
}

TEST_F(UntexturedGlTest, TheSkyIsAGradient) {
  const Scene scene = testing::streetScene();
  const glm::dvec3 o = kStreetOrigin;
  Diagnostics diag;
  RenderSettings settings;
  settings.blend.k = 1;  // at most one photograph here
  settings.depthSize = 256;
  Renderer renderer(scene, settings, diag);
  // Looking up at about 43 degrees: only sky in the view, from about 17 to 70 degrees elevation.
  const Camera view = testing::lookAt("up", o + glm::dvec3(0, -50, 2), o + glm::dvec3(0, -20, 30), 80, 60, 60);
  const RenderOutput out = renderer.render(view);
  const glm::dvec3 top = pixelColour(out.rgba, 40, 0), bottom = pixelColour(out.rgba, 40, 59);
  // Towards the zenith the sky is deeper blue, towards the horizon paler: the rows differ.
  EXPECT_GT(glm::length(top - bottom), 0.1);
  EXPECT_LT(top.r, bottom.r);
  for (int y = 0; y < 60; y += 7) {
    const glm::dvec3 want = skyColor(view.rayDirection({40.5, y + 0.5}), scene.up, settings.untextured);
    const glm::dvec3 got = pixelColour(out.rgba, 40, y);
    EXPECT_LT(glm::length(got - want) / std::sqrt(3.0) * 255.0, 1.5) << "row " << y;
    EXPECT_EQ(out.rgba.at(40, y, 3), 0);
  }
  // Each row is brighter red than the row above it (monotonic with elevation).
  for (int y = 1; y < 60; ++y) EXPECT_GE(out.rgba.at(40, y, 0), out.rgba.at(40, y - 1, 0)) << y;
}

TEST_F(UntexturedGlTest, SwitchedOffIsTheBackgroundColour) {
  const Scene scene = testing::streetScene();
  const glm::dvec3 o = kStreetOrigin;
  Diagnostics diag;
  RenderSettings settings;
  settings.blend.k = 1;  // at most one photograph here
  settings.depthSize = 256;
  settings.background = {0.2, 0.4, 0.6};
  settings.untextured.shading = false;
  settings.untextured.sky = false;
  Renderer renderer(scene, settings, diag);
  const Camera view = testing::lookAt("v", o + glm::dvec3(8, -11, 2.2), o + glm::dvec3(-3, 31, 12), 80, 60, 55);
  const RenderOutput off = renderer.render(view);
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 80; ++x) {
      ASSERT_EQ(off.rgba.at(x, y, 0), 51) << x << "," << y;
      ASSERT_EQ(off.rgba.at(x, y, 1), 102);
      ASSERT_EQ(off.rgba.at(x, y, 2), 153);
      ASSERT_EQ(off.rgba.at(x, y, 3), 0);
    }
  // Live: the sky alone back on changes the top row (sky), not the bottom one (ground).
  renderer.settings().untextured.sky = true;
  const RenderOutput skyOnly = renderer.render(view);
  EXPECT_NE(skyOnly.rgba.at(40, 0, 2), 153);
  EXPECT_EQ(skyOnly.rgba.at(40, 59, 2), 153);
  EXPECT_EQ(skyOnly.rgba.at(40, 0, 3), 0);
}

TEST_F(UntexturedGlTest, CoverageIsStillWhereAPhotographContributes) {
  Scene scene = testing::streetScene();
  const glm::dvec3 o = kStreetOrigin;
  // One pure-red photograph of the near building only (narrow field of view).
  const std::string dir = testing::makeTempDir("untextured");
  Photo p;
  p.camera = testing::lookAt("red", o + glm::dvec3(0, -10, 6), o + glm::dvec3(0, 10, 6), 64, 64, 200);
  p.imagePath = dir + "/red.png";
  writePng(p.imagePath, testing::solidImage(64, 64, 255, 0, 0));
  scene.photos.push_back(p);
  Diagnostics diag;
  RenderSettings settings;
  settings.blend.k = 1;  // at most one photograph here
  settings.depthSize = 256;
  Renderer renderer(scene, settings, diag);
  const Camera view = testing::lookAt("v", o + glm::dvec3(2, -14, 3), o + glm::dvec3(0, 20, 8), 120, 90, 120);
  const RenderOutput out = renderer.render(view);
  ASSERT_TRUE(diag.ok());
  int covered = 0, shaded = 0;
  for (int y = 0; y < 90; ++y)
    for (int x = 0; x < 120; ++x) {
      const std::uint8_t* px = &out.rgba.data[(size_t(y) * 120 + x) * 4];
      if (px[3] > 0) {
        ++covered;
        EXPECT_EQ(px[3], 255);
        EXPECT_GE(px[0], 250) << x << "," << y;  // the photograph's red (bilinear at its border)
        EXPECT_LE(px[1], 5);
      } else {
        // Not covered: shaded grey or sky, never the photograph's red nor black.
        ++shaded;
        EXPECT_GT(px[1], 25) << x << "," << y;
        EXPECT_GT(px[2], 25) << x << "," << y;
      }
    }
  EXPECT_GT(covered, 500);
  EXPECT_GT(shaded, 2000);
  // The counts agree with the alpha: a pixel is covered exactly where an image contributed.
  const RenderOutput counted = renderer.render(view, true);
  for (int y = 0; y < 90; ++y)
    for (int x = 0; x < 120; ++x)
      ASSERT_EQ(counted.counts.at(x, y, 0) > 0, counted.rgba.at(x, y, 3) > 0) << x << "," << y;
}

}  // namespace
}  // namespace hv::render
