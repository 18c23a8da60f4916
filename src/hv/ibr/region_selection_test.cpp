// Region selection (docs/design.md, steps 1 and 5): the frustum index, the per-cell candidates,
// and the per-pixel blend of the CPU reference against hand-computed values.
#include "hv/ibr/region_selection.h"

#include "hv/ibr/frame_plan.h"
#include "hv/ibr/reference_blend.h"
#include "hv/ibr/weights.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

namespace hv::ibr {
namespace {

// A pinhole camera at `center` looking at `target`, z up.
Camera look(const std::string& id, glm::dvec3 center, glm::dvec3 target, int w = 160, int h = 120,
            double focal = 100.0) {
  return lookAtCamera(id, center, target, w, h, focal, {0, 0, 1});
}

TEST(ClipRayToBox, StretchInsideTheBox) {
  Aabb b;
  b.extend({0, 0, 0});
  b.extend({10, 10, 10});
  double t0, t1;
  ASSERT_TRUE(clipRayToBox({-5, 5, 5}, {1, 0, 0}, b, t0, t1));
  EXPECT_DOUBLE_EQ(t0, 5.0);
  EXPECT_DOUBLE_EQ(t1, 15.0);
  ASSERT_TRUE(clipRayToBox({5, 5, 5}, {0, 0, -2}, b, t0, t1));  // from inside
  EXPECT_DOUBLE_EQ(t0, 0.0);
  EXPECT_DOUBLE_EQ(t1, 2.5);
  EXPECT_FALSE(clipRayToBox({-5, 5, 5}, {-1, 0, 0}, b, t0, t1));  // pointing away
  EXPECT_FALSE(clipRayToBox({-5, 20, 5}, {1, 0, 0}, b, t0, t1));  // parallel, outside
}

TEST(FrustumIndex, CellsListEveryPhotographWhoseFrustumContainsThePoint) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Aabb box;
  box.extend({-100, -100, 0});
  box.extend({100, 100, 30});
  std::vector<Camera> cams;
  for (int i = 0; i < 40; ++i) {
    const glm::dvec3 c(200 * u(rng) - 100, 200 * u(rng) - 100, 2 + 20 * u(rng));
    const double yaw = 2 * M_PI * u(rng);
    cams.push_back(look("c" + std::to_string(i), c, c + glm::dvec3(std::cos(yaw), std::sin(yaw), -0.3 * u(rng))));
  }
  const FrustumIndex index(cams, box, 2000);
  EXPECT_GT(index.cells().x, 1);
  EXPECT_GT(index.cells().z, 1);
  int inside = 0;
  for (int n = 0; n < 3000; ++n) {
    const glm::dvec3 P(200 * u(rng) - 100, 200 * u(rng) - 100, 30 * u(rng));
    const auto& listed = index.at(P);
    for (int i = 0; i < int(cams.size()); ++i) {
      // Independent: the camera's own projection.
      const Projection p = cams[size_t(i)].project(P);
      const bool seen = p.inFront && p.pxIdeal.x >= 0 && p.pxIdeal.y >= 0 && p.pxIdeal.x <= 160 && p.pxIdeal.y <= 120;
      // idealRectCoveringImage adds a pixel of margin: compare away from the border only.
      const bool clearlyOut =
          !p.inFront || p.pxIdeal.x < -2 || p.pxIdeal.y < -2 || p.pxIdeal.x > 162 || p.pxIdeal.y > 122;
      if (seen) {
        ++inside;
        EXPECT_TRUE(index.contains(i, P)) << "camera " << i;
        EXPECT_NE(std::find(listed.begin(), listed.end(), i), listed.end()) << "camera " << i << " not listed";
      }
      if (clearlyOut) EXPECT_FALSE(index.contains(i, P)) << "camera " << i;
    }
  }
  EXPECT_GT(inside, 500);
  // Outside the bounds: nothing.
  EXPECT_TRUE(index.at({0, 0, 100}).empty());
}

// Two streets 400 m apart, each with its own photographs looking along it (+y); the view sees
// both from above, nearer to street A.
struct TwoStreets {
  Scene scene;
  Aabb bounds;
  Camera view;
  TwoStreets() {
    for (int s = 0; s < 2; ++s)
      for (int i = 0; i < 10; ++i) {
        Photo p;
        const glm::dvec3 c(s * 400.0, 10.0 * i, 1.7);
        p.camera = look(std::string(s ? "b" : "a") + std::to_string(i), c, c + glm::dvec3(0, 20, -1));
        scene.photos.push_back(p);
      }
    bounds.extend({-30, -20, 0});
    bounds.extend({430, 200, 20});
    view = look("v", {150, -250, 250}, {200, 100, 0}, 320, 200, 160);
  }
  static bool inA(const Camera& c) { return c.id[0] == 'a'; }
};

TEST(RegionCandidates, EveryStreetGetsItsOwnPhotographs) {
  const TwoStreets t;
  std::vector<Camera> cams;
  std::vector<glm::dvec3> centers;
  for (const auto& p : t.scene.photos) {
    cams.push_back(p.camera);
    centers.push_back(p.camera.center);
  }
  const FrustumIndex frusta(cams, t.bounds);
  const CameraIndex index(centers);
  BlendSettings s;
  s.selection = Selection::Region;
  s.k = 4;
  s.sigma = 5.0;
  s.candidates = 8;
  const FramePlan region = planFrame(t.scene, index, t.view, s, t.bounds, &frusta);
  ASSERT_EQ(region.images.size(), 8u);
  int a = 0, b = 0;
  for (size_t i = 0; i < region.images.size(); ++i) {
    const auto& im = region.images[i];
    (TwoStreets::inA(t.scene.photos[size_t(im.photo)].camera) ? a : b) += 1;
    EXPECT_NEAR(im.distance, glm::length(t.scene.photos[size_t(im.photo)].camera.center - t.view.center), 1e-9);
    EXPECT_NEAR(im.weight, blendFalloff(im.distance, 5.0), 1e-15);  // f(d_i), not a global weight
    if (i > 0) EXPECT_LE(region.images[i - 1].distance, im.distance);
  }
  EXPECT_GE(a, 2);
  EXPECT_GE(b, 2);
  EXPECT_LT(region.nextDistance, 0.0);
  // The same plan builds its own index when given none.
  const FramePlan own = planFrame(t.scene, index, t.view, s, t.bounds);
  ASSERT_EQ(own.images.size(), region.images.size());
  for (size_t i = 0; i < own.images.size(); ++i) EXPECT_EQ(own.images[i].photo, region.images[i].photo);
  // Global: the K nearest to the view, all in street A (nearer); weights f(d_i) - f(d_K+1).
  s.selection = Selection::Global;
  const FramePlan global = planFrame(t.scene, index, t.view, s, t.bounds);
  ASSERT_EQ(global.images.size(), 4u);
  for (const auto& im : global.images) EXPECT_TRUE(TwoStreets::inA(t.scene.photos[size_t(im.photo)].camera));
  ASSERT_GT(global.nextDistance, 0.0);
  EXPECT_NEAR(global.images[0].weight,
              blendFalloff(global.images[0].distance, 5.0) - blendFalloff(global.nextDistance, 5.0), 1e-15);
}

TEST(RegionCandidates, FiltersAndCountApply) {
  const TwoStreets t;
  std::vector<glm::dvec3> centers;
  for (const auto& p : t.scene.photos) centers.push_back(p.camera.center);
  const CameraIndex index(centers);
  BlendSettings s;
  s.selection = Selection::Region;
  s.sigma = 5.0;
  s.candidates = 30;  // more than can see the view: every one that can
  for (const auto& p : t.scene.photos)
    if (p.camera.id == "b3" || p.camera.id == "a0") s.exclude.push_back(p.camera.id);
  const FramePlan plan = planFrame(t.scene, index, t.view, s, t.bounds);
  std::set<std::string> ids;
  for (const auto& im : plan.images) ids.insert(t.scene.photos[size_t(im.photo)].camera.id);
  EXPECT_FALSE(ids.count("b3"));
  EXPECT_FALSE(ids.count("a0"));
  EXPECT_EQ(ids.size(), 18u);  // all the others look into the view's part of the bounds
  // A photograph outside the bounds looking away from them is never a candidate.
  TwoStreets t2;
  Photo away;
  away.camera = look("away", {200, -100, 5}, {200, -200, 5});
  t2.scene.photos.push_back(away);
  centers.push_back(away.camera.center);
  const CameraIndex index2(centers);
  s.exclude.clear();
  const FramePlan plan2 = planFrame(t2.scene, index2, t2.view, s, t2.bounds);
  for (const auto& im : plan2.images) EXPECT_NE(t2.scene.photos[size_t(im.photo)].camera.id, "away");
  EXPECT_EQ(plan2.images.size(), 20u);
  // No geometry bounds: the nearest `candidates`.
  s.candidates = 3;
  const FramePlan noBounds = planFrame(t.scene, index, t.view, s, Aabb{});
  ASSERT_EQ(noBounds.images.size(), 3u);
  EXPECT_LE(noBounds.images[0].distance, noBounds.images[2].distance);
}

// Region blend, by hand: four images seeing P, f = 0.5, 0.2, 0.1, 0.05 (weights as the plan
// carries them), colours red, green, blue, white; K = 2.
class RegionBlend : public ::testing::Test {
 protected:
  void SetUp() override {
    PinholeFrustum fr;
    fr.pxMax = {160, 120};
    const double f[4] = {0.5, 0.2, 0.1, 0.05};
    for (int i = 0; i < 4; ++i) {
      const Camera c = look("c" + std::to_string(i), {0.2 * i, -10, 0}, {0, 0, 0});
      images.push_back(makeImageParams(c, {0, 0, 0}, {i, {1.0 / 160, 1.0 / 120}}, f[i], fr, {}));
    }
  }
  BlendResult blend(int k, std::set<size_t> hidden = {}) {
    return referenceBlend(
        P, images, BlendMethod::Blend, tex, [=](size_t i, const glm::dvec3&, double) { return !hidden.count(i); },
        Selection::Region, k);
  }
  std::vector<ImageParams> images;
  glm::dvec4 colour[4] = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}, {1, 1, 1, 1}};
  TextureLookup tex = [this](int slice, glm::dvec2) { return colour[slice]; };
  glm::dvec3 P{0, 0, 0};
};

TEST_F(RegionBlend, FirstKPassingWeightedAgainstTheNextPassing) {
  // All pass: w = (0.5 - 0.1, 0.2 - 0.1) = (0.4, 0.1).
  BlendResult r = blend(2);
  EXPECT_EQ(r.count, 2);
  EXPECT_NEAR(r.alpha, 0.5, 1e-12);
  EXPECT_NEAR(r.color.r, 0.8, 1e-12);
  EXPECT_NEAR(r.color.g, 0.2, 1e-12);
  EXPECT_NEAR(r.color.b, 0.0, 1e-12);
  EXPECT_NEAR(r.share(0), 0.8, 1e-12);
  // Image 1 occluded here: image 2 takes its place, image 3 is the K+1-th:
  // w = (0.5 - 0.05, 0.1 - 0.05) = (0.45, 0.05).
  r = blend(2, {1});
  EXPECT_EQ(r.count, 2);
  EXPECT_NEAR(r.alpha, 0.5, 1e-12);
  EXPECT_NEAR(r.color.r, 0.9, 1e-12);
  EXPECT_NEAR(r.color.g, 0.0, 1e-12);
  EXPECT_NEAR(r.color.b, 0.1, 1e-12);
  EXPECT_DOUBLE_EQ(r.contribution[1], 0.0);
  // A fully masked image does not count either (it does not show this surface): same as occluded.
  colour[1] = glm::dvec4(0.0);
  const BlendResult masked = blend(2);
  EXPECT_NEAR(masked.color.b, 0.1, 1e-12);
  EXPECT_NEAR(masked.alpha, 0.5, 1e-12);
  colour[1] = {0, 1, 0, 1};
  // Two of four pass: no K+1-th, f = 0: w = (0.5, 0.1) for images 0 and 3.
  r = blend(2, {1, 2});
  EXPECT_NEAR(r.alpha, 0.55, 1e-12);
  EXPECT_NEAR(r.color.r, (0.5 + 0.05) / 0.55, 1e-12);
  EXPECT_NEAR(r.color.b, 0.05 / 0.55, 1e-12);
  // A partial mask (premultiplied alpha 0.5) still passes: w a = 0.4 * 0.5.
  colour[0] = {0.5, 0, 0, 0.5};
  r = blend(2);
  EXPECT_NEAR(r.alpha, 0.4 * 0.5 + 0.1, 1e-12);
  EXPECT_NEAR(r.color.r, 0.2 / 0.3, 1e-12);
}

TEST_F(RegionBlend, EqualsGlobalWhenEveryImagePasses) {
  // Where nothing fails a test, the pixel's K+1-th is the frame's: the papers' weights.
  const std::vector<double> d = {1.0, 2.0, 3.0, 4.0};
  for (int k = 1; k <= 4; ++k) {
    for (size_t i = 0; i < 4; ++i) images[i].weight = blendFalloff(d[i], 1.5);
    const std::vector<double> w = blendWeights(d, k, 1.5);
    std::vector<ImageParams> global(images.begin(), images.begin() + long(w.size()));
    for (size_t i = 0; i < w.size(); ++i) global[i].weight = w[i];
    const BlendResult r = blend(k);
    const BlendResult g = referenceBlend(P, global, BlendMethod::Blend, tex, {});
    EXPECT_EQ(r.count, g.count) << "K = " << k;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.color[c], g.color[c], 1e-12) << "K = " << k;
    EXPECT_NEAR(r.alpha, g.alpha, 1e-12) << "K = " << k;
  }
}

TEST_F(RegionBlend, TieWithTheNextGivesNoWeightAndNearestTakesTheFirstPassing) {
  images[1].weight = images[2].weight = 0.1;  // the 2nd ties with the 3rd (K+1-th)
  BlendResult r = blend(2);
  EXPECT_EQ(r.count, 1);
  EXPECT_NEAR(r.color.r, 1.0, 1e-12);
  // Nearest: the first that passes, K or not.
  r = referenceBlend(
      P, images, BlendMethod::Nearest, tex, [](size_t i, const glm::dvec3&, double) { return i > 0; },
      Selection::Region, 2);
  EXPECT_NEAR(r.color.g, 1.0, 1e-12);
  EXPECT_EQ(r.count, 1);
}

}  // namespace
}  // namespace hv::ibr
