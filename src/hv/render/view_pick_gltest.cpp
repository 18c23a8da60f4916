// Picking from the view depth (Renderer::pickViewPoint, render/view_pick.h) against the CPU ray
// cast (Embree) of the demo city's geometry: the point the picture shows under a pixel.
#include "hv/render/renderer.h"
#include "hv/render/testing/gl_test_support.h"
#include "hv/scene/native/raycast.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>

namespace hv::render {
namespace {

class ViewPickGlTest : public testing::GlTest {};

TEST_F(ViewPickGlTest, PickedPointIsTheRayCastOfTheDemoCity) {
  const testing::DemoCity& city = testing::demoCity();
  const Scene& scene = city.scene;
  ASSERT_FALSE(city.views.empty());
  // A held-out view, at a small size (the test's cost is the ray casts' and the read-backs').
  const Camera& full = city.views[0].camera;
  Camera view = full.scaled(160.0 / full.width, 160, int(std::lround(full.height * 160.0 / full.width)));
  view.distortion.reset();  // a pinhole view: its depth texels are its pixels
  Diagnostics diag;
  RenderSettings settings;
  settings.points.enabled = false;  // the geometry the ray cast sees
  Renderer renderer(scene, settings, diag);
  EXPECT_FALSE(renderer.pickViewPoint({10.5, 10.5})) << "nothing to pick before the first frame";
  renderer.render(view);

  Mesh all = scene.terrain;
  all.append(scene.buildings);
  all.append(scene.mesh);
  const RayCaster caster(all);
  int compared = 0, sky = 0;
  double worst = 0.0;
  for (int y = 2; y < view.height; y += 7)
    for (int x = 2; x < view.width; x += 7) {
      const glm::dvec2 px(x + 0.5, y + 0.5);  // pixel centres: the view-depth texels' (pinhole view)
      const glm::dvec2 ideal = view.undistort(px).value();
      const auto hit = caster.intersect(view.center, view.rayDirection(ideal), 0.0, 1e9);
      const auto picked = renderer.pickViewPoint(px);
      if (!hit) {
        EXPECT_FALSE(picked) << "sky at " << x << "," << y;
        ++sky;
        continue;
      }
      // Away from depth edges, where a pixel's sample may fall on either side.
      bool flat = true;
      for (glm::dvec2 off : {glm::dvec2(1.5, 0), glm::dvec2(-1.5, 0), glm::dvec2(0, 1.5), glm::dvec2(0, -1.5)}) {
        const auto ideal2 = view.undistort(px + off);
        const auto h2 = ideal2 ? caster.intersect(view.center, view.rayDirection(*ideal2), 0.0, 1e9) : std::nullopt;
        flat = flat && h2 && glm::dot(h2->normal, hit->normal) > 0.999;
      }
      if (!flat) continue;
      ASSERT_TRUE(picked) << "nothing picked at " << x << "," << y;
      const double d = glm::distance(*picked, hit->position);
      // A few centimetres: the depth's 24-bit packing of [near, far] (far - near of a few hundred
      // metres: below a millimetre) and the rasteriser's float positions about the render origin.
      EXPECT_LT(d, 0.03) << "at " << x << "," << y << ", " << hit->t << " m away";
      worst = std::max(worst, d);
      ++compared;
    }
  EXPECT_GE(compared, 150);
  std::cout << "view pick: " << compared << " pixels against the ray cast, worst " << worst * 100.0 << " cm; " << sky
            << " sky pixels\n";
  EXPECT_FALSE(renderer.pickViewPoint({-1.0, 5.0}));
  EXPECT_FALSE(renderer.pickViewPoint({5.0, double(view.height)}));
  EXPECT_TRUE(diag.ok());
}

}  // namespace
}  // namespace hv::render
