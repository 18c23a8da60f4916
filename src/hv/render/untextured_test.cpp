// The untextured look (render/untextured.h) against values worked out by hand from its formulas.
#include "hv/render/untextured.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv::render {
namespace {

// Exact up to double rounding: the expected values are sums of a few products.
constexpr double kTol = 1e-12;

void expectNear(const glm::dvec3& got, const glm::dvec3& want, double tol = kTol) {
  EXPECT_NEAR(got.x, want.x, tol);
  EXPECT_NEAR(got.y, want.y, tol);
  EXPECT_NEAR(got.z, want.z, tol);
}

TEST(Untextured, TangentFrameIsRightHandedAroundUp) {
  const TangentFrame z = tangentFrame({0, 0, 2});
  expectNear(z.east, {1, 0, 0});
  expectNear(z.north, {0, 1, 0});
  expectNear(z.up, {0, 0, 1});
  // y up (a glTF-like scene): east stays x, north is -z.
  const TangentFrame y = tangentFrame({0, 1, 0});
  expectNear(y.east, {1, 0, 0});
  expectNear(y.north, {0, 0, -1});
  // x up: east is y made horizontal.
  const TangentFrame x = tangentFrame({1, 0, 0});
  expectNear(x.east, {0, 1, 0});
  expectNear(x.north, {0, 0, 1});
  for (const TangentFrame& f : {z, y, x}) expectNear(glm::cross(f.east, f.north), f.up);
}

TEST(Untextured, SunDirectionFollowsAzimuthAndElevation) {
  UntexturedSettings s;
  s.sunAzimuthDeg = 90.0;  // east
  s.sunElevationDeg = 0.0;
  expectNear(sunDirection({0, 0, 1}, s), {1, 0, 0});
  s.sunAzimuthDeg = 180.0;  // south
  expectNear(sunDirection({0, 0, 1}, s), {0, -1, 0});
  s.sunElevationDeg = 90.0;
  expectNear(sunDirection({0, 0, 5}, s), {0, 0, 1});
  // The defaults: azimuth 150, elevation 45: (cos 45 sin 150, cos 45 cos 150, sin 45).
  const double h = std::sqrt(0.5);
  expectNear(sunDirection({0, 0, 1}, UntexturedSettings{}), {h * 0.5, -h * std::sqrt(3.0) / 2.0, h});
}

TEST(Untextured, ShadingIsLambertUnderHemisphereAndSun) {
  UntexturedSettings s;   // albedo (0.80, 0.80, 0.78), sky (0.55, 0.57, 0.62), ground (0.22, 0.21, 0.20)
  s.sunAzimuthDeg = 0.0;  // sun (0.50, 0.49, 0.46)
  s.sunElevationDeg = 90.0;
  // Facing up, sun overhead: albedo * (sky + sun).
  expectNear(shadeUntextured({0, 0, 1}, {0, 0, 1}, s), {0.80 * 1.05, 0.80 * 1.06, 0.78 * 1.08});
  // Facing down: the ground light alone.
  expectNear(shadeUntextured({0, 0, -1}, {0, 0, 1}, s), {0.80 * 0.22, 0.80 * 0.21, 0.78 * 0.20});
  // A wall: half sky, half ground; the sun at the horizon straight in front of it.
  s.sunAzimuthDeg = 90.0;
  s.sunElevationDeg = 0.0;
  expectNear(shadeUntextured({1, 0, 0}, {0, 0, 2}, s),
             {0.80 * (0.385 + 0.50), 0.80 * (0.39 + 0.49), 0.78 * (0.41 + 0.46)});
  // The wall behind it gets no sun.
  expectNear(shadeUntextured({-1, 0, 0}, {0, 0, 1}, s), {0.80 * 0.385, 0.80 * 0.39, 0.78 * 0.41});
  // The sun at 60 degrees above a south wall: cos 60 = 1/2 of it.
  s.sunAzimuthDeg = 180.0;
  s.sunElevationDeg = 60.0;
  expectNear(shadeUntextured({0, -1, 0}, {0, 0, 1}, s),
             {0.80 * (0.385 + 0.25), 0.80 * (0.39 + 0.245), 0.78 * (0.41 + 0.23)});
  // Brighter than white is clamped.
  s.albedo = glm::dvec3(1.0);
  s.skyLight = glm::dvec3(0.9);
  s.sunLight = glm::dvec3(0.9);
  s.sunElevationDeg = 90.0;
  expectNear(shadeUntextured({0, 0, 1}, {0, 0, 1}, s), glm::dvec3(1.0));
}

TEST(Untextured, SurfacesAreNeitherBackgroundNorBlack) {
  // Every facing direction, with the default settings, is lit: at least albedo * groundLight, and
  // far from the default black background.
  const UntexturedSettings s;
  for (int i = 0; i <= 12; ++i)
    for (int j = 0; j < 24; ++j) {
      const double theta = M_PI * i / 12.0, phi = 2.0 * M_PI * j / 24.0;
      const glm::dvec3 n{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
      const glm::dvec3 c = shadeUntextured(n, {0, 0, 1}, s);
      EXPECT_GT(std::min({c.r, c.g, c.b}), 0.15) << theta << " " << phi;
      EXPECT_LE(std::max({c.r, c.g, c.b}), 1.0);
    }
  // Up-facing surfaces (roofs, the DTM) are brighter than down-facing ones, and a wall facing the
  // sun brighter than the one facing away.
  EXPECT_GT(shadeUntextured({0, 0, 1}, {0, 0, 1}, s).g, shadeUntextured({0, 0, -1}, {0, 0, 1}, s).g);
  const glm::dvec3 sun = sunDirection({0, 0, 1}, s);
  const glm::dvec3 towards = glm::normalize(glm::dvec3(sun.x, sun.y, 0.0));
  EXPECT_GT(shadeUntextured(towards, {0, 0, 1}, s).g, shadeUntextured(-towards, {0, 0, 1}, s).g + 0.2);
}

TEST(Untextured, SkyIsAGradientFromHorizonToZenith) {
  UntexturedSettings s;
  s.horizon = {0.8, 0.9, 1.0};
  s.zenith = {0.2, 0.4, 0.8};
  expectNear(skyColor({0, 0, 3}, {0, 0, 1}, s), s.zenith);
  expectNear(skyColor({1, 2, 0}, {0, 0, 1}, s), s.horizon);
  expectNear(skyColor({0, 1, -1}, {0, 0, 1}, s), s.horizon);  // below the horizon
  // 30 degrees up: sin = 1/2, the mix at sqrt(1/2).
  const double t = std::sqrt(0.5);
  expectNear(skyColor({std::sqrt(3.0), 0, 1}, {0, 0, 1}, s),
             {0.8 + t * (0.2 - 0.8), 0.9 + t * (0.4 - 0.9), 1.0 + t * (0.8 - 1.0)});
  // Along another up vector.
  expectNear(skyColor({0, 4, 0}, {0, 2, 0}, s), s.zenith);
  // The defaults differ at the zenith and at the horizon.
  const UntexturedSettings d;
  EXPECT_GT(glm::length(skyColor({0, 0, 1}, {0, 0, 1}, d) - skyColor({1, 0, 0}, {0, 0, 1}, d)), 0.3);
}

}  // namespace
}  // namespace hv::render
