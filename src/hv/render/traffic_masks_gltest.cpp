// The traffic composited into the demo city's views (the 2013 paper, §3: the photographs are
// "unpopulated" by their masks of moving vehicles, the view "repopulated" by the simulation):
// - no doubled car: where a masked photograph's own cars would be projected into a held-out view
//   (found on the CPU by ray casting the cars the demo put in that photograph), the render with
//   the masks shows the empty street of the view's ground truth, and the render without them shows
//   the photographed car (so the check fails when masking does not work);
// - the empty street without the traffic: the render with the traffic switched off is that of the
//   scene without any;
// - the simulated vehicle where the CPU ray cast of its model says, the rest of the view unchanged.
#include "hv/demo/demo_city.h"
#include "hv/image/image.h"
#include "hv/image/native/png_write.h"
#include "hv/render/renderer.h"
#include "hv/render/testing/gl_test_support.h"
#include "hv/render/vehicles.h"
#include "hv/scene/native/raycast.h"
#include "hv/traffic/lift.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>

namespace hv::render {
namespace {

using testing::demoCity;

class TrafficMasksGlTest : public testing::GlTest {};

constexpr double kInf = std::numeric_limits<double>::infinity();

// The renderer's proxy geometry (terrain and LOD1 buildings) for the CPU references.
Mesh proxyOf(const Scene& scene) {
  Mesh all = scene.terrain;
  all.append(scene.buildings);
  return all;
}

// The view pixels where a masked photograph's own cars would be drawn without the mask: the proxy
// point seen through the pixel is visible from the photograph, inside it, and the photograph's ray
// to it passes through one of its cars first.
struct DoubledCar {
  int photo = -1;
  std::vector<int> pixels;  // y * width + x, away from the cars' silhouettes
};

// Whether the proxy point seen by `view` at pixel `px` shows a car of `shot` in the photograph.
// 1: a car, 0: the street, -1: not seen by the photograph (outside it, hidden, sky).
int seenThroughCar(const Camera& view, glm::dvec2 px, const RayCaster& proxy, const demo::Shot& shot,
                   const RayCaster& cars) {
  const glm::dvec3 dir = glm::normalize(view.rayDirection(px));
  const auto hit = proxy.intersect(view.center, dir, 0.0, 1e9);
  if (!hit) return -1;
  const Camera& cam = shot.camera;
  const Projection pr = cam.project(hit->position);
  if (!pr.inImage || pr.pxIdeal.x < 2 || pr.pxIdeal.y < 2 || pr.pxIdeal.x > cam.width - 2 ||
      pr.pxIdeal.y > cam.height - 2)
    return -1;
  const glm::dvec3 toP = hit->position - cam.center;
  const double d = glm::length(toP);
  const glm::dvec3 u = toP / d;
  if (proxy.occluded(cam.center, u, 0.0, d - 0.05)) return -1;  // the proxy hides it from the photograph
  return cars.occluded(cam.center, u, 0.0, d - 0.05) ? 1 : 0;
}

TEST_F(TrafficMasksGlTest, NoDoubledCarsWhereMaskedAndTheSimulatedOnesWhereTheirBoxesProject) {
  const testing::DemoCity& city = demoCity();
  const Scene& scene = city.scene;
  // The photographs' cars, as the demo placed them (a pure function of the options: the same plan
  // as the one the city was written from).
  demo::DemoOptions options;
  options.traffic.enabled = false;
  const demo::World world = demo::buildWorld(options);
  const RayCaster truthCaster(world.truth.mesh);
  const demo::ShotPlan plan = demo::planShots(world, truthCaster);
  ASSERT_EQ(plan.photos.size(), scene.photos.size());
  for (size_t i = 0; i < plan.photos.size(); ++i) {
    ASSERT_EQ(plan.photos[i].camera.id, scene.photos[i].camera.id);
    ASSERT_EQ(plan.photos[i].masked, !scene.photos[i].maskPath.empty()) << plan.photos[i].camera.id;
  }

  const Mesh proxyMesh = proxyOf(scene);
  const RayCaster proxy(proxyMesh);
  // The masked photograph whose cars would show over the most pixels of a view: a coarse search
  // over every view, then every pixel of the one found.
  const auto doubledPixels = [&](const Camera& view, const demo::Shot& shot, int step) {
    const RayCaster cars(shot.cars.mesh);
    std::vector<int> pixels;
    for (int y = 2; y < view.height - 2; y += step)
      for (int x = 2; x < view.width - 2; x += step) {
        const glm::dvec2 c(x + 0.5, y + 0.5);
        if (seenThroughCar(view, c, proxy, shot, cars) != 1) continue;
        bool inside = true;  // away from the silhouettes (the mask is dilated by 2 px)
        for (glm::dvec2 off : {glm::dvec2(3, 0), glm::dvec2(-3, 0), glm::dvec2(0, 3), glm::dvec2(0, -3)})
          inside = inside && seenThroughCar(view, c + off, proxy, shot, cars) == 1;
        if (inside) pixels.push_back(y * view.width + x);
      }
    return pixels;
  };
  int bestView = -1, bestPhoto = -1;
  size_t bestCount = 0;
  for (size_t v = 0; v < city.views.size(); ++v)
    for (size_t p = 0; p < plan.photos.size(); ++p) {
      const demo::Shot& shot = plan.photos[p];
      if (!shot.masked || shot.cars.mesh.empty()) continue;
      const size_t n = doubledPixels(city.views[v].camera, shot, 6).size();
      if (n > bestCount) {
        bestCount = n;
        bestView = int(v);
        bestPhoto = int(p);
      }
    }
  ASSERT_GE(bestView, 0) << "no masked photograph's cars fall in a view";
  const Camera& view = city.views[size_t(bestView)].camera;
  const std::vector<int> doubled = doubledPixels(view, plan.photos[size_t(bestPhoto)], 1);
  ASSERT_GE(doubled.size(), 500u) << view.id;

  // The renders, with the masks and without, against the view's ground truth (no vehicles).
  Diagnostics diag;
  RenderSettings settings;
  settings.blend.k = 8;
  Renderer renderer(scene, settings, diag);
  const RenderOutput masked = renderer.render(view);
  renderer.settings().blend.masks = false;
  const RenderOutput unmasked = renderer.render(view);
  renderer.settings().blend.masks = true;
  const Image8 truth = readImage((std::filesystem::path(city.summary.truthDir) / (view.id + ".png")).string(), 3);
  ASSERT_EQ(truth.width, view.width);
  const auto error = [&](const RenderOutput& r, int i) {
    int e = 0;
    for (int k = 0; k < 3; ++k)
      e = std::max(e, std::abs(int(r.rgba.data[4 * size_t(i) + k]) - int(truth.data[3 * size_t(i) + k])));
    return e;
  };
  double sumMasked = 0.0, sumUnmasked = 0.0;
  int carMasked = 0, carUnmasked = 0;  // pixels off the truth by more than 40 levels
  for (int i : doubled) {
    sumMasked += error(masked, i);
    sumUnmasked += error(unmasked, i);
    carMasked += error(masked, i) > 40;
    carUnmasked += error(unmasked, i) > 40;
  }
  const double n = double(doubled.size());
  std::cout << "view " << view.id << ", photograph " << plan.photos[size_t(bestPhoto)].camera.id << ": "
            << doubled.size() << " pixels under its cars; largest channel error to the truth: mean " << sumMasked / n
            << " with the masks, " << sumUnmasked / n << " without; over 40 levels: " << carMasked << " with, "
            << carUnmasked << " without\n";
  // Masked, the photographed cars are gone: the street as in the truth, as near as the blend
  // elsewhere; unmasked, they show (measured: mean 5.0 and 30.0 levels, 209 and 3,665 pixels).
  EXPECT_LT(sumMasked / n, 10.0);
  EXPECT_GT(sumUnmasked / n, 2.0 * sumMasked / n + 8.0);
  EXPECT_LT(carMasked, int(0.04 * n));
  EXPECT_GT(carUnmasked, 4 * carMasked + int(0.1 * n));

  // The traffic: one simulated car on the street where the photographed ones were, heading along
  // it. Switched off, the view is the empty street (the scene without traffic, byte for byte).
  const RenderOutput empty = renderer.render(view);
  EXPECT_EQ(empty.rgba.data, masked.rgba.data);
  int sx = 0, sy = 0;
  for (int i : doubled) {
    sx += i % view.width;
    sy += i / view.width;
  }
  const glm::dvec2 centre(double(sx) / n + 0.5, double(sy) / n + 0.5);
  const auto ground = proxy.intersect(view.center, glm::normalize(view.rayDirection(centre)), 0.0, 1e9);
  ASSERT_TRUE(ground.has_value());
  ASSERT_TRUE(world.onRoad(ground->position.x, ground->position.y));
  double heading = 0.0, nearest = kInf;  // along the nearest street's centre line
  for (const demo::Street& st : world.streets) {
    const double d = std::abs((st.alongX ? ground->position.y : ground->position.x) - st.centre);
    if (d < nearest) {
      nearest = d;
      heading = st.alongX ? 90.0 : 0.0;
    }
  }
  Scene withTraffic = scene;
  auto traffic = std::make_shared<Trajectories>();
  Trajectory car;
  car.id = "car";
  for (int k = 0; std::max({vehicleColour(car.id).r, vehicleColour(car.id).g, vehicleColour(car.id).b}) -
                      std::min({vehicleColour(car.id).r, vehicleColour(car.id).g, vehicleColour(car.id).b}) <
                  0.4f;
       ++k)
    car.id = "car" + std::to_string(k);  // a paint far from grey
  car.type = "passenger";
  car.size = vehicleSizeOf(car.type);
  car.samples = {{0.0, glm::dvec2(ground->position), heading}, {10.0, glm::dvec2(ground->position), heading}};
  traffic->vehicles.push_back(car);
  traffic->tEnd = 10.0;
  withTraffic.traffic = traffic;
  settings.traffic.time = 5.0;
  Renderer trafficRenderer(withTraffic, settings, diag);
  const RenderOutput with = trafficRenderer.render(view);
  trafficRenderer.settings().traffic.enabled = false;
  EXPECT_EQ(trafficRenderer.render(view).rgba.data, masked.rgba.data) << "--no-traffic is not the empty street";

  // The CPU reference: the car's model (the built-in box with wheels) as lifted onto the terrain.
  const MeshTerrainHeight terrain(scene.terrain);
  const std::vector<VehicleInstance> vehicles = vehicleInstances(*traffic, terrain, 5.0, scene.origin);
  ASSERT_EQ(vehicles.size(), 1u);
  const VehicleInstance& vi = vehicles[0];
  enum class Seen { Vehicle, Hidden, Street, Shadow };
  const auto classify = [&](glm::dvec2 px) {
    const glm::dvec3 dir = glm::normalize(view.rayDirection(px));
    const auto hit = proxy.intersect(view.center, dir, 0.0, 1e9);
    const double tScene = hit ? hit->t : kInf;
    const double tVehicle = rayVehicleEntry(vi, nullptr, view.center - scene.origin, dir);
    if (tVehicle >= 0.0) return tVehicle < tScene ? Seen::Vehicle : Seen::Hidden;
    if (!hit) return Seen::Street;
    // Under the contact shadow (1.12 times the footprint), with a margin.
    const glm::dvec3 q = hit->position - scene.origin - glm::dvec3(vi.position);
    const bool under = std::abs(glm::dot(q, glm::dvec3(vi.forward))) < 0.6 * vi.size.x + 0.3 &&
                       std::abs(glm::dot(q, glm::dvec3(vi.right))) < 0.6 * vi.size.y + 0.3;
    return under ? Seen::Shadow : Seen::Street;
  };
  int shown = 0, unchanged = 0, wrong = 0;
  for (int y = 1; y < view.height - 1; ++y)
    for (int x = 1; x < view.width - 1; ++x) {
      const glm::dvec2 c(x + 0.5, y + 0.5);
      const Seen seen = classify(c);
      if (seen == Seen::Shadow) continue;
      bool robust = true;  // away from silhouettes: rasterisation and the ray cast may differ there
      for (glm::dvec2 off : {glm::dvec2(1.5, 0), glm::dvec2(-1.5, 0), glm::dvec2(0, 1.5), glm::dvec2(0, -1.5)})
        robust = robust && classify(c + off) == seen;
      if (!robust) continue;
      const size_t i = size_t(y) * view.width + x;
      int diff = 0;
      for (int k = 0; k < 3; ++k)
        diff = std::max(diff, std::abs(int(with.rgba.data[4 * i + k]) - int(masked.rgba.data[4 * i + k])));
      if (seen == Seen::Vehicle) {
        shown += diff > 10;
        wrong += diff <= 10;
      } else {
        unchanged += diff == 0;
        wrong += diff != 0;
      }
    }
  std::cout << "the simulated car: " << shown << " pixels drawn where its box projects, " << unchanged
            << " of the street unchanged, " << wrong << " wrong\n";
  EXPECT_GT(shown, 300);
  EXPECT_EQ(wrong, 0);
  EXPECT_TRUE(diag.ok());
  if (HasFailure()) {
    const std::string dir = testing::makeTempDir("traffic-masks-gltest");
    writePng(dir + "/masked.png", masked.rgba);
    writePng(dir + "/unmasked.png", unmasked.rgba);
    writePng(dir + "/with-traffic.png", with.rgba);
    ADD_FAILURE() << "the pictures are in " << dir;
  }
}

}  // namespace
}  // namespace hv::render
