// Viewpoints from the command line (session/viewpoint.h): expected values from the projection
// written out by hand (a pinhole camera at a known place), not from the code under test.
#include "hv/session/viewpoint.h"

#include "hv/session/checks.h"
#include "hv/viewer/navigation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace hv::app {
namespace {

Scene sceneWithPhotos() {
  Scene s;
  s.path = "scene.json";
  s.origin = {1000.0, 2000.0, 0.0};
  Photo a;
  a.camera = lookAtCamera("a", {1000, 2000, 10}, {1050, 2000, 10}, 400, 300, 300);
  Photo b;
  b.camera = lookAtCamera("b", {1010, 2000, 10}, {1010, 2050, 10}, 400, 300, 300);
  s.photos = {a, b};
  return s;
}

TEST(Viewpoint, ParsesThreeNumbersAndNamesTheOptionOtherwise) {
  EXPECT_EQ(parseVec3("--eye", "1.5,-2,3e2"), glm::dvec3(1.5, -2, 300));
  for (const std::string bad : {"1,2", "1,2,3,4", "a,b,c", "1 2 3", "1,2,nan", ""}) {
    try {
      parseVec3("--eye", bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("--eye: expected X,Y,Z"), std::string::npos) << e.what();
    }
  }
}

TEST(Viewpoint, EyeCameraLooksAtItsTargetWithTheGivenFieldOfView) {
  const Scene scene = sceneWithPhotos();
  ViewpointOptions o;
  o.eye = "1000,2000,20";
  o.lookAt = "1100,2030,5";
  o.fovDeg = 90.0;
  const Camera c = eyeCamera(scene, o, 640, 480);
  EXPECT_EQ(c.center, glm::dvec3(1000, 2000, 20));
  // 90 degrees across 640 pixels: focal = 320 / tan(45 deg) = 320.
  EXPECT_NEAR(c.focal.x, 320.0, 1e-9);
  const Projection p = c.project({1100, 2030, 5});
  EXPECT_NEAR(glm::length(p.pxIdeal - glm::dvec2(320, 240)), 0.0, 1e-9);
  // No roll: the image x axis is horizontal, and a point above the target is higher in the image.
  EXPECT_NEAR(glm::transpose(c.camFromWorld)[0].z, 0.0, 1e-12);
  EXPECT_LT(c.project({1100, 2030, 15}).pxIdeal.y, 240.0);
  // --local: the same point given in the render frame.
  o.local = true;
  o.eye = "0,0,20";
  o.lookAt = "100,30,5";
  EXPECT_NEAR(glm::length(eyeCamera(scene, o, 640, 480).center - glm::dvec3(1000, 2000, 20)), 0.0, 1e-12);
}

TEST(Viewpoint, EyeErrorsNameWhatIsMissing) {
  const Scene scene = sceneWithPhotos();
  ViewpointOptions o;
  o.eye = "0,0,0";
  EXPECT_THROW(eyeCamera(scene, o, 64, 48), std::invalid_argument);
  o.lookAt = "0,0,10";  // straight up: no image up
  try {
    eyeCamera(scene, o, 64, 48);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("up axis"), std::string::npos) << e.what();
  }
}

TEST(Viewpoint, CameraIdsPickPhotographsThenViewsInTheOrderGiven) {
  const Scene scene = sceneWithPhotos();
  Photo v;
  v.camera = lookAtCamera("v1", {0, 0, 1}, {1, 0, 1}, 64, 48, 50);
  ViewpointOptions o;
  o.cameras = {"v1", "b"};
  const auto views = viewpointViews(scene, {v}, o, "");
  ASSERT_EQ(views.size(), 2u);
  EXPECT_EQ(views[0].camera.id, "v1");
  EXPECT_EQ(views[1].camera.center, scene.photos[1].camera.center);
  o.cameras = {"nope"};
  try {
    viewpointViews(scene, {v}, o, "");
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("--camera nope"), std::string::npos) << m;
    EXPECT_NE(m.find("a, b, v1"), std::string::npos) << m;  // the ids that exist
  }
}

TEST(Viewpoint, StepBackMovesAlongTheAxisAndWidensTheView) {
  const Scene scene = sceneWithPhotos();
  ViewpointOptions o;
  o.cameras = {"a"};
  o.stepBack = 12.0;
  const Camera c = viewpointViews(scene, {}, o, "")[0].camera;
  // a looks along +x from (1000, 2000, 10): 12 back is x = 988.
  EXPECT_NEAR(glm::length(c.center - glm::dvec3(988, 2000, 10)), 0.0, 1e-9);
  EXPECT_NEAR(c.focal.x, 300.0 * o.zoomOut, 1e-9);
  EXPECT_EQ(c.id, "a");
  // The photograph's axis still lands on the image centre.
  EXPECT_NEAR(glm::length(c.project({1100, 2000, 10}).pxIdeal - glm::dvec2(200, 150)), 0.0, 1e-9);
}

TEST(Viewpoint, StepBackFromAnUpsideDownPhotographGivesAnUprightView) {
  Scene scene = sceneWithPhotos();
  Camera& a = scene.photos[0].camera;
  a.camFromWorld = glm::dmat3(-1, 0, 0, 0, -1, 0, 0, 0, 1) * a.camFromWorld;  // rolled 180 degrees
  EXPECT_NEAR(std::abs(viewer::rollOf(a, scene.up)), std::numbers::pi, 1e-9);
  ViewpointOptions o;
  o.cameras = {"a"};
  o.stepBack = 5.0;
  const Camera c = viewpointViews(scene, {}, o, "")[0].camera;
  EXPECT_NEAR(viewer::rollOf(c, scene.up), 0.0, 1e-9);
  EXPECT_LT(c.project({1100, 2000, 20}).pxIdeal.y, c.project({1100, 2000, 0}).pxIdeal.y) << "sky above";
}

TEST(Viewpoint, AnotherAspectRatioIsCroppedOrPaddedAboutTheCentre) {
  const Camera v = lookAtCamera("v", {0, 0, 0}, {10, 0, 0}, 400, 300, 300);
  const glm::dvec3 onAxis(10, 0, 0);
  // Crop to 200x200: scale max(200/400, 200/300) = 2/3, the sides cut off.
  const Camera crop = fitView(v, 200, 200, Fit::Crop);
  EXPECT_EQ(crop.width, 200);
  EXPECT_NEAR(crop.focal.x, 200.0, 1e-9);
  EXPECT_NEAR(glm::length(crop.project(onAxis).pxIdeal - glm::dvec2(100, 100)), 0.0, 1e-9);
  // The original frame's top edge (y = 0) lands on the output's top edge, its left edge outside.
  const glm::dvec3 topCentre = v.center + v.rayDirection({200, 0}) * 10.0;
  EXPECT_NEAR(crop.project(topCentre).pxIdeal.y, 0.0, 1e-9);
  const glm::dvec3 leftCentre = v.center + v.rayDirection({0, 150}) * 10.0;
  EXPECT_NEAR(crop.project(leftCentre).pxIdeal.x, 100.0 - 400.0 / 3.0, 1e-9);
  // Pad to 200x200: scale min = 1/2, bands above and below.
  const Camera pad = fitView(v, 200, 200, Fit::Pad);
  EXPECT_NEAR(pad.focal.x, 150.0, 1e-9);
  EXPECT_NEAR(pad.project(leftCentre).pxIdeal.x, 0.0, 1e-9);
  EXPECT_NEAR(pad.project(topCentre).pxIdeal.y, 100.0 - 75.0, 1e-9);
  // Same aspect: as resized.
  EXPECT_EQ(fitView(v, 200, 150, Fit::Pad).focal, v.resized(200, 150).focal);
  EXPECT_EQ(sizeView(v, "200x200", "pad").focal, pad.focal);
  EXPECT_THROW(sizeView(v, "200x200", "stretch"), std::invalid_argument);
}

TEST(Viewpoint, ARefusedSizeNamesTheNearestThatFits) {
  // 16000x9000 against MAX_TEXTURE_SIZE 8192: x 0.512 -> 8192x4608 (41.9 MP, under the 64 MP cap).
  EXPECT_EQ(nearestValidViewSize(16000, 9000, 8192), glm::ivec2(8192, 4608));
  Camera big = lookAtCamera("big", {0, 0, 0}, {10, 0, 0}, 16000, 9000, 300);
  EXPECT_NE(viewSizeProblem(big, 8192).find("--size 8192x4608"), std::string::npos) << viewSizeProblem(big, 8192);
  // Over the pixel cap only: 10000 x 10000 with no texture limit -> sqrt(2^26 / 1e8) = 0.8192.
  EXPECT_EQ(nearestValidViewSize(10000, 10000, 0), glm::ivec2(8192, 8192));
  EXPECT_EQ(viewSizeProblem(lookAtCamera("ok", {0, 0, 0}, {10, 0, 0}, 8192, 4608, 300), 8192), "");
}

}  // namespace
}  // namespace hv::app
