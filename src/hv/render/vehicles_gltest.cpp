// The traffic composited into the view on llvmpipe (the 2013 paper, §3: the Z-buffer against the
// image-based render's depth): at sampled pixels, a vehicle shows exactly where a CPU ray cast
// finds its boxes nearer than the scene's geometry, so that one behind a building is hidden and
// one in front of a façade hides it; elsewhere the picture is that of the empty street.
#include "hv/render/renderer.h"

#include "hv/image/native/png_write.h"
#include "hv/render/testing/gl_test_support.h"
#include "hv/render/vehicles.h"
#include "hv/scene/native/raycast.h"
#include "hv/traffic/lift.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hv::render {
namespace {

using testing::kStreetOrigin;

class VehiclesGlTest : public testing::GlTest {};

// An id whose paint is far from grey, so that a vehicle pixel cannot pass for a shaded wall.
std::string colourfulId(int start) {
  for (int k = start;; ++k) {
    const glm::vec3 c = vehicleColour("car" + std::to_string(k));
    if (std::max({c.r, c.g, c.b}) - std::min({c.r, c.g, c.b}) > 0.4f) return "car" + std::to_string(k);
  }
}

Trajectory parked(const std::string& id, glm::dvec2 xy, double angleDeg) {
  Trajectory t;
  t.id = id;
  t.type = "passenger";
  t.size = vehicleSizeOf("car");
  t.samples = {{0.0, xy, angleDeg}, {10.0, xy, angleDeg}};
  return t;
}

TEST_F(VehiclesGlTest, HiddenBehindABuildingAndHidingAFacade) {
  Scene scene = testing::streetScene();  // the near building: x in [-5, 5], y in [10, 14], 12 m high
  const glm::dvec3 o = kStreetOrigin;
  auto traffic = std::make_shared<Trajectories>();
  // Behind the near building, half past its east corner as seen from the view; in front of its
  // façade, heading north.
  traffic->vehicles.push_back(parked(colourfulId(0), glm::dvec2(o) + glm::dvec2(7.0, 20.0), 90.0));
  traffic->vehicles.push_back(parked(colourfulId(100), glm::dvec2(o) + glm::dvec2(-1.0, 5.0), 0.0));
  traffic->tEnd = 10.0;
  scene.traffic = traffic;

  Diagnostics diag;
  RenderSettings settings;
  settings.blend.k = 1;
  settings.depthSize = 256;
  settings.traffic.time = 5.0;
  Renderer renderer(scene, settings, diag);
  const Camera view = testing::lookAt("v", o + glm::dvec3(0, -10, 2.0), o + glm::dvec3(2, 20, 2.0), 240, 180, 200);
  const RenderOutput with = renderer.render(view);
  renderer.settings().traffic.enabled = false;
  const RenderOutput without = renderer.render(view);
  ASSERT_EQ(with.rgba.width, 240);
  ASSERT_EQ(without.rgba.width, 240);

  // The CPU reference: the scene's surfaces by ray casting, the vehicles' models (the built-in box
  // with wheels) as placed on the terrain (render/vehicles.h), in the render frame.
  const VehicleModels* models = nullptr;
  Mesh all = scene.terrain;
  all.append(scene.buildings);
  const RayCaster caster(all);
  const MeshTerrainHeight terrain(scene.terrain);
  const std::vector<VehicleInstance> vehicles = vehicleInstances(*traffic, terrain, 5.0, scene.origin);
  ASSERT_EQ(vehicles.size(), 2u);
  enum class Seen { Vehicle, Hidden, None };
  const auto classify = [&](glm::dvec2 px, int* which) {
    const glm::dvec3 dir = view.rayDirection(px);
    const auto hit = caster.intersect(view.center, dir, 0.0, 1e9);
    const double tScene = hit ? hit->t : std::numeric_limits<double>::infinity();
    double tVehicle = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < vehicles.size(); ++i) {
      const double t = rayVehicleEntry(vehicles[i], models, view.center - scene.origin, dir);
      if (t >= 0.0 && t < tVehicle) {
        tVehicle = t;
        if (which) *which = int(i);
      }
    }
    if (!std::isfinite(tVehicle)) return Seen::None;
    return tVehicle < tScene ? Seen::Vehicle : Seen::Hidden;
  };
  int shown[2] = {0, 0}, hidden[2] = {0, 0};
  for (int y = 1; y < view.height - 1; y += 2)
    for (int x = 1; x < view.width - 1; x += 2) {
      int which = -1;
      const glm::dvec2 c(x + 0.5, y + 0.5);
      const Seen seen = classify(c, &which);
      if (seen == Seen::None) continue;  // the empty street, or a contact shadow on it
      // Away from silhouettes: rasterisation and the ray cast may differ by a pixel there.
      bool robust = true;
      for (glm::dvec2 off : {glm::dvec2(1.5, 0), glm::dvec2(-1.5, 0), glm::dvec2(0, 1.5), glm::dvec2(0, -1.5)})
        robust = robust && classify(c + off, nullptr) == seen;
      if (!robust) continue;
      const std::uint8_t* a = &with.rgba.data[(size_t(y) * view.width + x) * 4];
      const std::uint8_t* b = &without.rgba.data[(size_t(y) * view.width + x) * 4];
      int diff = 0;
      for (int k = 0; k < 3; ++k) diff = std::max(diff, std::abs(int(a[k]) - int(b[k])));
      if (seen == Seen::Vehicle) {
        EXPECT_GT(diff, 10) << "a vehicle in front of the geometry is not drawn at (" << x << ", " << y << ")";
        ++shown[which];
      } else {
        EXPECT_EQ(diff, 0) << "a vehicle behind the geometry shows at (" << x << ", " << y << ")";
        ++hidden[which];
      }
    }
  // The one behind the building: partly hidden, partly seen past its corner; the one in front of
  // the façade: seen, nothing of it hidden.
  EXPECT_GT(hidden[0], 10);
  EXPECT_GT(shown[0], 5);
  EXPECT_GT(shown[1], 50);
  EXPECT_EQ(hidden[1], 0);
  if (HasFailure()) {
    const std::string dir = testing::makeTempDir("vehicles-gltest");
    writePng(dir + "/with-traffic.png", with.rgba);
    writePng(dir + "/without-traffic.png", without.rgba);
    ADD_FAILURE() << "the pictures are in " << dir;
  }
  // Switched off, the picture has no vehicle at all: the empty street.
  RenderSettings none = settings;
  none.traffic.enabled = false;
  Scene empty = testing::streetScene();
  Renderer emptyRenderer(empty, none, diag);
  EXPECT_EQ(emptyRenderer.render(view).rgba.data, without.rgba.data);
}

}  // namespace
}  // namespace hv::render
