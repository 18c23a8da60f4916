#include "hv/traffic/lift.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The plane z = z0 + a x + b y, meshed over [-50, 50]^2 as a grid of 10 m cells.
Mesh planeMesh(double z0, double a, double b) {
  Mesh m;
  const int n = 10;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = -50.0 + 10.0 * i, y = -50.0 + 10.0 * j;
      m.positions.emplace_back(x, y, z0 + a * x + b * y);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const auto at = [&](int ii, int jj) { return unsigned(jj * (n + 1) + ii); };
      m.triangles.emplace_back(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      m.triangles.emplace_back(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return m;
}

TEST(MeshTerrainHeight, HeightsOnAPlaneAndNothingOffIt) {
  const MeshTerrainHeight h(planeMesh(100.0, 0.1, -0.05));
  for (const glm::dvec2 p : {glm::dvec2(0, 0), glm::dvec2(13.7, -42.1), glm::dvec2(-50, 50), glm::dvec2(20, 20)}) {
    ASSERT_TRUE(h.heightAt(p.x, p.y).has_value()) << p.x << " " << p.y;
    EXPECT_NEAR(*h.heightAt(p.x, p.y), 100.0 + 0.1 * p.x - 0.05 * p.y, 1e-9);
  }
  EXPECT_FALSE(h.heightAt(50.5, 0).has_value());
  EXPECT_FALSE(h.heightAt(0, -60).has_value());
}

TEST(MeshTerrainHeight, TakesTheTopSurfaceAndIgnoresVerticalSkirts) {
  Mesh m = planeMesh(0.0, 0.0, 0.0);
  // A vertical strip (a skirt) along x = 5 going down 3 m: seen edge-on from above.
  const unsigned base = unsigned(m.positions.size());
  m.positions.insert(m.positions.end(), {{5, -10, 0}, {5, 10, 0}, {5, 10, -3}, {5, -10, -3}});
  m.triangles.emplace_back(base, base + 1, base + 2);
  m.triangles.emplace_back(base, base + 2, base + 3);
  const MeshTerrainHeight h(m);
  EXPECT_NEAR(*h.heightAt(5.0, 0.0), 0.0, 1e-12);
  EXPECT_NEAR(*h.heightAt(5.000001, 1.0), 0.0, 1e-12);
}

// Heading: the vehicle's forward axis is SUMO's angle, clockwise from north (+y).
TEST(LiftOntoTerrain, HeadingIsTheSimulatorsAngle) {
  const MeshTerrainHeight flat(planeMesh(7.0, 0.0, 0.0));
  const VehicleSize car;
  for (const auto& [angle, forward] :
       {std::pair{0.0, glm::dvec3(0, 1, 0)}, std::pair{90.0, glm::dvec3(1, 0, 0)},
        std::pair{180.0, glm::dvec3(0, -1, 0)}, std::pair{270.0, glm::dvec3(-1, 0, 0)}}) {
    const auto pose = liftOntoTerrain({{1, 2}, angle}, car, flat);
    ASSERT_TRUE(pose.has_value());
    const glm::dvec3 f = pose->worldFromVehicle * glm::dvec3(0, 1, 0);
    EXPECT_NEAR(glm::length(f - forward), 0.0, 1e-12) << angle;
    const glm::dvec3 up = pose->worldFromVehicle * glm::dvec3(0, 0, 1);
    EXPECT_NEAR(glm::length(up - glm::dvec3(0, 0, 1)), 0.0, 1e-12);
    EXPECT_NEAR(pose->position.z, 7.0, 1e-12);
    EXPECT_NEAR(pose->pitch, 0.0, 1e-12);
    EXPECT_NEAR(pose->roll, 0.0, 1e-12);
  }
  // Right is 90 degrees clockwise from forward seen from above: heading north, right is east.
  const auto north = liftOntoTerrain({{0, 0}, 0.0}, car, flat);
  EXPECT_NEAR(glm::length(north->worldFromVehicle * glm::dvec3(1, 0, 0) - glm::dvec3(1, 0, 0)), 0.0, 1e-12);
}

// Every wheel on a sloped plane, whatever the heading.
TEST(LiftOntoTerrain, WheelsOnASlopedPlaneWithinOneCentimetre) {
  const double a = 0.12, b = -0.07;  // 12 % rising east, 7 % falling north
  const MeshTerrainHeight plane(planeMesh(50.0, a, b));
  const VehicleSize bus{12.0, 2.5, 3.4};
  for (double angle = 0.0; angle < 360.0; angle += 22.5) {
    const auto pose = liftOntoTerrain({{3.3, -7.9}, angle}, bus, plane);
    ASSERT_TRUE(pose.has_value());
    for (const glm::dvec3& w : wheelContacts(*pose, bus)) EXPECT_NEAR(w.z, 50.0 + a * w.x + b * w.y, 0.01) << angle;
    EXPECT_NEAR(pose->position.z, 50.0 + a * 3.3 + b * -7.9, 0.01);
    // The body's up axis is the plane's normal.
    const glm::dvec3 up = pose->worldFromVehicle * glm::dvec3(0, 0, 1);
    const glm::dvec3 n = glm::normalize(glm::dvec3(-a, -b, 1.0));
    EXPECT_NEAR(glm::length(up - n), 0.0, 1e-9) << angle;
  }
}

// Pitch and roll against the slope: driving up a 10 % slope pitches the nose up by atan(0.1);
// across it, the downhill side is lower by the roll atan(0.1).
TEST(LiftOntoTerrain, PitchAndRollFromTheSlope) {
  const MeshTerrainHeight rampNorth(planeMesh(0.0, 0.0, 0.1));  // rises towards +y
  const VehicleSize car;
  const auto up = liftOntoTerrain({{0, 0}, 0.0}, car, rampNorth);  // driving north: uphill
  EXPECT_NEAR(up->pitch, std::atan(0.1), 1e-9);
  EXPECT_NEAR(up->roll, 0.0, 1e-9);
  const auto down = liftOntoTerrain({{0, 0}, 180.0}, car, rampNorth);
  EXPECT_NEAR(down->pitch, -std::atan(0.1), 1e-9);
  // Driving east, north (uphill) is on the left: the right side is lower, a positive roll.
  const auto east = liftOntoTerrain({{0, 0}, 90.0}, car, rampNorth);
  EXPECT_NEAR(east->pitch, 0.0, 1e-9);
  EXPECT_NEAR(east->roll, std::atan(0.1), 1e-9);
  const auto west = liftOntoTerrain({{0, 0}, 270.0}, car, rampNorth);
  EXPECT_NEAR(west->roll, -std::atan(0.1), 1e-9);
  // At 45 degrees on the ramp, the slope splits into pitch and roll: sin(pitch) = 0.1 cos45 / |..|.
  const auto diag = liftOntoTerrain({{0, 0}, 45.0}, car, rampNorth);
  EXPECT_NEAR(diag->pitch, std::atan(0.1 * std::cos(kPi / 4)), 1e-9);
}

TEST(LiftOntoTerrain, OffTheTerrainIsNotLifted) {
  const MeshTerrainHeight plane(planeMesh(0.0, 0.0, 0.0));
  EXPECT_FALSE(liftOntoTerrain({{80, 0}, 0.0}, VehicleSize{}, plane).has_value());
  // At the edge, the wheels off it take the centre's height.
  const auto edge = liftOntoTerrain({{50, 0}, 0.0}, VehicleSize{}, plane);
  ASSERT_TRUE(edge.has_value());
  EXPECT_NEAR(edge->position.z, 0.0, 1e-12);
}

}  // namespace
}  // namespace hv
