// The scene's scale (scene/scene_scale.h) on synthetic streets whose distances are known by
// construction: a façade 10 m in front of the cameras, rig stations 8 m apart.
#include "hv/scene/scene_scale.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace hv {
namespace {

// A façade: the plane y = 10, x in [-20, 60], z in [0, 12], a vertex every metre.
Mesh facade() {
  Mesh m;
  for (int x = -20; x <= 60; ++x)
    for (int z = 0; z <= 12; ++z) m.positions.push_back({double(x), 10.0, double(z)});
  m.triangles.push_back({0, 1, 2});
  return m;
}

// A street of `stations` rig positions 8 m apart along x; at each, `headings` cameras 0.1 m apart
// looking horizontally at 0, +60, -60 degrees from +y (towards the façade).
std::vector<Photo> rigStreet(int stations, int headings) {
  std::vector<Photo> photos;
  const double angles[] = {0.0, 60.0, -60.0};
  for (int s = 0; s < stations; ++s)
    for (int k = 0; k < headings; ++k) {
      const double a = angles[k] * std::numbers::pi / 180.0;
      const glm::dvec3 c(8.0 * s + 0.1 * k, 0.0, 1.5);
      Photo p;
      p.camera = lookAtCamera("s" + std::to_string(s) + "c" + std::to_string(k), c,
                              c + glm::dvec3(std::sin(a), std::cos(a), 0.0), 400, 300, 200);
      photos.push_back(p);
    }
  return photos;
}

TEST(SceneScale, CamerasFacingAFacadeTenMetresAway) {
  Scene scene;
  scene.mesh = facade();
  scene.photos = rigStreet(5, 1);
  const SceneScale s = sceneScale(scene);
  // Every façade point a camera looking along +y sees is 10 m deep (depth along the axis).
  EXPECT_NEAR(s.surfaceDistance, 10.0, 1e-9);
  EXPECT_NEAR(s.spacing, 8.0, 1e-9);
  EXPECT_NEAR(s.scale, 10.0, 1e-9);
  EXPECT_NE(s.source.find("camera-to-surface"), std::string::npos);
  EXPECT_NEAR(s.extent, std::sqrt(80.0 * 80.0 + 12.0 * 12.0), 1e-9);  // the façade's box (no depth)
  EXPECT_TRUE(s.outlying.empty());
}

TEST(SceneScale, ARigDoesNotShrinkTheSpacing) {
  // Cameras 0.1 m apart within a rig (the old camera spacing), 8 m between stations.
  Scene scene;
  scene.photos = rigStreet(6, 3);
  EXPECT_NEAR(scene.cameraSpacing(), 0.1, 1e-9);
  const SceneScale s = sceneScale(scene);
  EXPECT_NEAR(s.spacing, 8.0, 1e-9);
  EXPECT_EQ(s.surfaceDistance, 0.0);  // no geometry
  EXPECT_NEAR(s.scale, 8.0, 1e-9);
}

TEST(SceneScale, AFarCameraIsNamedAndDoesNotSetTheScale) {
  Scene scene;
  scene.mesh = facade();
  scene.photos = rigStreet(5, 1);
  Photo far = scene.photos[0];
  far.camera.id = "lost";
  far.camera.center = {414000.0, 0.0, 1.5};
  scene.photos.push_back(far);
  const SceneScale s = sceneScale(scene);
  ASSERT_EQ(s.outlying.size(), 1u);
  EXPECT_EQ(s.outlying[0], 5u);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("camera 'lost'"), std::string::npos) << s.warnings[0];
  EXPECT_NE(s.warnings[0].find("left out of the scene's scale"), std::string::npos) << s.warnings[0];
  EXPECT_NEAR(s.spacing, 8.0, 1e-9);
  EXPECT_NEAR(s.scale, 10.0, 1e-9);
}

TEST(SceneScale, PhotographsHundredsOfKilometresApartInAMetricCrsAreAllOutlying) {
  // As the MicMac orientations of three historical photographs (ECEF, 414 km apart), no geometry:
  // in metres no street is photographed from 5 km apart, so none sets the scale.
  Scene scene;
  scene.crs = "EPSG:4978";
  scene.photos = rigStreet(3, 1);
  for (size_t i = 0; i < 3; ++i) scene.photos[i].camera.center.x = 414000.0 * double(i);
  const SceneScale s = sceneScale(scene);
  EXPECT_EQ(s.outlying.size(), 3u);
  EXPECT_EQ(s.scale, kDefaultScale);
  EXPECT_NE(s.source.find("default"), std::string::npos);
  // Without a CRS the units are unknown: the cameras are all there is, and set the scale.
  scene.crs.clear();
  EXPECT_TRUE(sceneScale(scene).outlying.empty());
  EXPECT_NEAR(sceneScale(scene).scale, 414000.0, 1e-6);
}

TEST(SceneScale, PanoramasAcrossACityWithoutGeometryKeepAStreetLevelScale) {
  // As the Stereopolis sample: rigs of 3 cameras 0.1 m apart, the stations a kilometre apart, no
  // geometry, in metres. The spacing (1000 m) is measured but the scale stays at street level.
  Scene scene;
  scene.crs = "EPSG:2154";
  scene.photos = rigStreet(6, 3);
  for (size_t i = 0; i < scene.photos.size(); ++i)  // 8 m -> 1000 m between stations
    scene.photos[i].camera.center.x = 1000.0 * double(i / 3) + 0.1 * double(i % 3);
  const SceneScale s = sceneScale(scene);
  EXPECT_NEAR(s.spacing, 1000.0, 1e-6);
  EXPECT_EQ(s.scale, kMetricSpacingScale[1]);
  EXPECT_NE(s.source.find("street level"), std::string::npos) << s.source;
  EXPECT_TRUE(s.outlying.empty());
}

}  // namespace
}  // namespace hv
