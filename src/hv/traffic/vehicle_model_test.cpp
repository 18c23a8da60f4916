#include "hv/traffic/vehicle_model.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv {
namespace {

TEST(VehicleModel, ClassesByTypeName) {
  EXPECT_EQ(vehicleClassOf("DEFAULT_VEHTYPE"), VehicleClass::Car);
  EXPECT_EQ(vehicleClassOf("passenger"), VehicleClass::Car);
  EXPECT_EQ(vehicleClassOf("City_Bus"), VehicleClass::Bus);
  EXPECT_EQ(vehicleClassOf("coach"), VehicleClass::Bus);
  EXPECT_EQ(vehicleClassOf("delivery"), VehicleClass::Truck);
  EXPECT_EQ(vehicleClassOf("trailer"), VehicleClass::Truck);
  EXPECT_EQ(vehicleClassOf("moped"), VehicleClass::Motorcycle);
  EXPECT_EQ(vehicleClassOf("bicycle"), VehicleClass::Bicycle);
  EXPECT_EQ(vehicleClassOf(""), VehicleClass::Car);
  EXPECT_STREQ(vehicleClassName(VehicleClass::Truck), "truck");
}

// The built-in model: inside the unit box, its wheels on the ground under the axles, each triangle
// wound counter-clockwise from outside (its normal agrees with its winding).
TEST(VehicleModel, BoxWithWheelsFillsTheUnitBox) {
  const VehicleModel& m = boxWithWheelsModel();
  ASSERT_EQ(m.vertices.size() % 3, 0u);
  glm::vec3 lo(1e9f), hi(-1e9f);
  int tyreOnGround = 0;
  for (std::size_t i = 0; i < m.vertices.size(); i += 3) {
    const glm::vec3 a = m.vertices[i].local, b = m.vertices[i + 1].local, c = m.vertices[i + 2].local;
    EXPECT_GT(glm::dot(glm::cross(b - a, c - a), m.vertices[i].normal), 0.0f) << "triangle " << i / 3;
    for (const glm::vec3& p : {a, b, c}) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    if (m.vertices[i].paint == 0.0f && a.z == 0.0f && b.z == 0.0f && c.z == 0.0f) ++tyreOnGround;
  }
  EXPECT_EQ(lo, glm::vec3(-0.5f, -0.5f, 0.0f));
  EXPECT_EQ(hi, glm::vec3(0.5f, 0.5f, 1.0f));
  EXPECT_EQ(tyreOnGround, 8);  // four wheels, two triangles under each
}

// A sloped face in metres, fitted to the unit box and scaled back by a vehicle of the model's own
// size: the normal the fit gives, divided by the size (vehicles.vert), is normal to the face again.
TEST(VehicleModel, FitKeepsNormalsNormalOnceScaled) {
  VehicleModel m;
  const glm::vec3 a(-1, -2, 0), b(1, -2, 0), c(0, 2, 1.5f);  // width 2, length 4, height 1.5
  const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
  m.vertices = {{a, n}, {b, n}, {c, n}};
  ASSERT_TRUE(fitToUnitBox(m));
  EXPECT_NEAR(m.vertices[2].local.z, 1.0f, 1e-6);
  EXPECT_NEAR(m.vertices[0].local.x, -0.5f, 1e-6);
  EXPECT_NEAR(m.vertices[2].local.y, 0.5f, 1e-6);
  const glm::vec3 span(2, 4, 1.5f);
  const glm::vec3 scaledNormal = m.vertices[0].normal / span;
  const glm::vec3 edge1 = (m.vertices[1].local - m.vertices[0].local) * span,
                  edge2 = (m.vertices[2].local - m.vertices[0].local) * span;
  EXPECT_NEAR(glm::dot(scaledNormal, edge1), 0.0f, 1e-6);
  EXPECT_NEAR(glm::dot(scaledNormal, edge2), 0.0f, 1e-6);
  // A flat model cannot be fitted.
  VehicleModel flat;
  flat.vertices = {{{0, 0, 0}}, {{1, 0, 0}}, {{0, 1, 0}}};
  EXPECT_FALSE(fitToUnitBox(flat));
}

// The ray cast against the built-in model, placed at (10, 0, 0) heading north, 4 x 2 x 1.5 m:
// a ray from the west at mid-body height enters the body's side (x = 10 - 0.48 * 2) ...
TEST(VehicleModel, RayMeetsThePlacedModel) {
  const glm::dvec3 pos(10, 0, 0), right(1, 0, 0), fwd(0, 1, 0), up(0, 0, 1), size(4, 2, 1.5);
  // (The model's fractions are floats: 0.48f is 0.48 to 1e-8, times the 2 m width.)
  const double t = rayModelEntry(boxWithWheelsModel(), pos, right, fwd, up, size, {0, 0, 0.5}, {1, 0, 0});
  EXPECT_NEAR(t, 10.0 - 0.48 * 2.0, 1e-7);
  // ... from above, the cabin's roof at 1.5 m; a ray passing beside it misses.
  EXPECT_NEAR(rayModelEntry(boxWithWheelsModel(), pos, right, fwd, up, size, {10, 0, 10}, {0, 0, -1}), 8.5, 1e-9);
  EXPECT_LT(rayModelEntry(boxWithWheelsModel(), pos, right, fwd, up, size, {0, 5, 0.5}, {1, 0, 0}), 0.0);
}

}  // namespace
}  // namespace hv
