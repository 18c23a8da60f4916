#include "hv/pose/geopose.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv::pose {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A camera at the origin of an ENU world (world = ENU) looking along `forward`.
glm::dvec4 quaternionLooking(glm::dvec3 forward, glm::dvec3 up = {0, 0, 1}) {
  const Camera c = lookAtCamera("c", glm::dvec3(0.0), forward, 100, 100, 100.0, up);
  return quaternionOf(enuFromCameraObject(c.camFromWorld, glm::dmat3(1.0)));
}

void expectQuaternion(const glm::dvec4& q, const glm::dvec4& expected) {
  // q and -q are the same rotation; quaternionOf returns w >= 0.
  const glm::dvec4 e = expected.w < 0.0 ? -expected : expected;
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(q[i], e[i], 1e-12) << "component " << i;
}

TEST(GeoPose, LevelCameraLookingNorthIsTheIdentity) { expectQuaternion(quaternionLooking({0, 1, 0}), {0, 0, 0, 1}); }

TEST(GeoPose, LookingEastIsAYawOfMinus90Degrees) {
  // Yaw turns about up, counter-clockwise seen from above: north to east is -90°.
  expectQuaternion(quaternionLooking({1, 0, 0}), {0, 0, -std::sin(45 * kDeg), std::cos(45 * kDeg)});
  expectQuaternion(quaternionLooking({-1, 0, 0}), {0, 0, std::sin(45 * kDeg), std::cos(45 * kDeg)});
}

TEST(GeoPose, PitchIsAboutTheObjectsXAxis) {
  // North, 30° up: a turn of +30° about east (x), which lifts the forward axis y towards z.
  expectQuaternion(quaternionLooking({0, std::cos(30 * kDeg), std::sin(30 * kDeg)}),
                   {std::sin(15 * kDeg), 0, 0, std::cos(15 * kDeg)});
}

TEST(GeoPose, TheStandardsWorkedExample) {
  // OGC 21-056r11's example: yaw 5.514456741060452, pitch -0.43610515937237904, roll 0 rad is the
  // quaternion (0.20054473382601948, -0.08111675703887213, 0.3660908114262869, -0.9050852994339209)
  // — yaw about z, then pitch about the turned x. A camera looking along that yaw and pitch:
  const double yaw = 5.514456741060452, pitch = -0.43610515937237904;
  // Forward is the object's y axis: north turned by the yaw (counter-clockwise) and the pitch.
  const glm::dvec3 forward(-std::sin(yaw) * std::cos(pitch), std::cos(yaw) * std::cos(pitch), std::sin(pitch));
  expectQuaternion(quaternionLooking(forward),
                   {0.20054473382601948, -0.08111675703887213, 0.3660908114262869, -0.9050852994339209});
}

TEST(GeoPose, QuaternionAndMatrixRoundTrip) {
  for (const glm::dvec3 f : {glm::dvec3(0.3, -0.9, -0.2), glm::dvec3(-0.99, 0.05, 0.1), glm::dvec3(0.01, 0.02, -1.0)}) {
    const Camera c = lookAtCamera("c", glm::dvec3(0.0), f, 100, 100, 100.0, glm::dvec3(0, 1, 0.2));
    const glm::dmat3 m = enuFromCameraObject(c.camFromWorld, glm::dmat3(1.0));
    const glm::dmat3 back = rotationOf(quaternionOf(m));
    for (int col = 0; col < 3; ++col)
      for (int row = 0; row < 3; ++row) EXPECT_NEAR(back[col][row], m[col][row], 1e-12);
    // The object's forward axis (y, the matrix's second column) is the camera's viewing direction.
    const glm::dvec3 y = m[1];
    EXPECT_NEAR(glm::dot(y, glm::normalize(f)), 1.0, 1e-12);
  }
}

TEST(GeoPose, EnuAxesAtKnownPlaces) {
  // At lat 0, lon 0: east is ECEF y, north z, up x.
  const glm::dmat3 m = enuFromEcef(0.0, 0.0);
  const glm::dvec3 east = glm::transpose(m)[0], north = glm::transpose(m)[1], up = glm::transpose(m)[2];
  EXPECT_NEAR(glm::distance(east, glm::dvec3(0, 1, 0)), 0.0, 1e-15);
  EXPECT_NEAR(glm::distance(north, glm::dvec3(0, 0, 1)), 0.0, 1e-15);
  EXPECT_NEAR(glm::distance(up, glm::dvec3(1, 0, 0)), 0.0, 1e-15);
  // At the north pole, lon 90°: up is z, north -y, east -x.
  const glm::dmat3 p = glm::transpose(enuFromEcef(90.0, 90.0));
  EXPECT_NEAR(glm::distance(p[2], glm::dvec3(0, 0, 1)), 0.0, 1e-15);
  EXPECT_NEAR(glm::distance(p[1], glm::dvec3(0, -1, 0)), 0.0, 1e-15);
  EXPECT_NEAR(glm::distance(p[0], glm::dvec3(-1, 0, 0)), 0.0, 1e-15);
}

TEST(GeoPose, JsonLayout) {
  GeoPose g;
  g.latDeg = 46.5, g.lonDeg = 3.0, g.heightM = 120.25, g.quaternion = {0.0, 0.0, -0.5, 0.75};
  EXPECT_EQ(geoPoseJson(g),
            "{\n  \"position\": {\"lat\": 46.5, \"lon\": 3, \"h\": 120.25},\n"
            "  \"quaternion\": {\"x\": 0, \"y\": 0, \"z\": -0.5, \"w\": 0.75}\n}\n");
}

}  // namespace
}  // namespace hv::pose
