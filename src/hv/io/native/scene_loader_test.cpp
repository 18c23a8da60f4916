#include "hv/io/native/scene_loader.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

class SceneLoaderInput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv_scene_loader_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string scene(const std::string& text) const {
    std::ofstream((dir_ / "scene.json").string()) << text;
    return (dir_ / "scene.json").string();
  }
  // The message loadScene refuses the scene with ("" when it loads).
  std::string refusal(const std::string& text) const {
    Diagnostics diag;
    try {
      loadScene(scene(text), diag);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(SceneLoaderInput, UnknownKeysRefuseTheSceneWithTheNearestKnownOne) {
  const std::string top = refusal(R"({"terain": {"path": "dtm.tif"}})");
  EXPECT_NE(top.find("scene.json: unknown key 'terain' (did you mean 'terrain'?)"), std::string::npos) << top;
  const std::string nested = refusal(R"({"cameras": {"paht": "cameras.json"}})");
  EXPECT_NE(nested.find("cameras: unknown key 'paht' (did you mean 'path'?)"), std::string::npos) << nested;
  EXPECT_EQ(refusal(R"({"up": [0, 0, 1]})"), "");
}

// "terrain": {"height": h}: a flat ground at h under the data, with a margin (at least 200 m),
// the buildings standing on it.
TEST_F(SceneLoaderInput, ATerrainHeightGivesAGroundPlaneUnderTheData) {
  std::ofstream((dir_ / "b.geojson").string()) << R"({"type": "FeatureCollection", "features": [{"type": "Feature",
    "properties": {"height": 12}, "geometry": {"type": "Polygon", "coordinates": [[[0,0],[10,0],[10,4],[0,4],[0,0]]]}}]})";
  Diagnostics diag;
  const Scene s = loadScene(scene(R"({"terrain": {"height": 35}, "buildings": {"path": "b.geojson"}})"), diag);
  EXPECT_TRUE(diag.ok()) << diag.errors.front();
  const Aabb b = s.buildings.bounds();
  EXPECT_EQ(b.lo.z, 35.0);  // the base on the ground, not at 0
  EXPECT_EQ(b.hi.z, 47.0);
  const Aabb t = s.terrain.bounds();
  EXPECT_EQ(t.lo.z, 35.0);
  EXPECT_EQ(t.hi.z, 35.0);
  EXPECT_NEAR(t.lo.x, 0.0 - 200.0, 1e-9);  // the footprint's extent and the 200 m margin
  EXPECT_NEAR(t.hi.x, 10.0 + 200.0, 1e-9);
  EXPECT_NEAR(t.lo.y, 0.0 - 200.0, 1e-9);
  EXPECT_NEAR(t.hi.y, 4.0 + 200.0, 1e-9);
  EXPECT_NEAR(s.terrain.area(), 410.0 * 404.0, 1e-6);
  for (const glm::uvec3& tri : s.terrain.triangles) {  // up-facing
    const glm::dvec3 n = glm::cross(s.terrain.positions[tri.y] - s.terrain.positions[tri.x],
                                    s.terrain.positions[tri.z] - s.terrain.positions[tri.x]);
    ASSERT_GT(n.z, 0.0);
  }
  EXPECT_NE(refusal(R"({"terrain": {"height": 35, "path": "dtm.tif"}})").find("terrain: expected either a path"),
            std::string::npos);
  EXPECT_NE(refusal(R"({"terrain": {"height": "35m"}})").find("terrain.height: expected the ground's elevation"),
            std::string::npos);
}

TEST_F(SceneLoaderInput, ACrsThatIsNotAStringRefusesTheScene) {
  const std::string m = refusal(R"({"crs": 12345})");
  EXPECT_NE(m.find("scene.json: crs: expected a CRS string"), std::string::npos) << m;
  EXPECT_NE(m.find("12345"), std::string::npos) << m;
}

TEST_F(SceneLoaderInput, FifosAndDevicesAsSourcesAreLeftOutAtOnce) {
  // A FIFO would block the open until a writer comes, a device would be read without end: each
  // source is left out, named, and the scene still loads.
  ASSERT_EQ(::mkfifo((dir_ / "cameras.json").c_str(), 0600), 0);
  ASSERT_EQ(::mkfifo((dir_ / "dtm.tif").c_str(), 0600), 0);
  Diagnostics diag;
  loadScene(scene(R"({"terrain": {"path": "dtm.tif"}, "mesh": {"path": "/dev/zero"},
                      "cameras": {"path": "cameras.json"}})"),
            diag);
  ASSERT_EQ(diag.errors.size(), 3u);
  EXPECT_NE(diag.errors[0].find("dtm.tif: raster: a FIFO"), std::string::npos) << diag.errors[0];
  EXPECT_NE(diag.errors[1].find("/dev/zero: mesh: a device"), std::string::npos) << diag.errors[1];
  EXPECT_NE(diag.errors[2].find("cameras.json: cameras file: a FIFO"), std::string::npos) << diag.errors[2];
}

TEST_F(SceneLoaderInput, TheSceneFileItselfIsCheckedBeforeItIsOpened) {
  Diagnostics diag;
  EXPECT_THROW(loadScene("/dev/zero", diag), InputError);
  ASSERT_EQ(::mkfifo((dir_ / "pipe.json").c_str(), 0600), 0);
  EXPECT_THROW(loadScene((dir_ / "pipe.json").string(), diag), InputError);
}

}  // namespace
}  // namespace hv
