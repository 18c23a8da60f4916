// The up axis of a scene without a CRS (hv/scene/scene_frame.h settleUp, which the native loader
// calls): inferred from the cameras' image up, as `info` then says; a declared up that the cameras
// contradict is named.
#include "hv/io/native/scene_loader.h"
#include "hv/scene/scene_scale.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

// Three cameras of an SfM frame whose up is -z: each looks horizontally (along x, y, -x) with its
// image up (-y of the camera) along world -z, i.e. camera y along +z.
std::string camerasJson() {
  // Rows of R are the camera axes in the world: x, y (image down), z (forward).
  const char* rotations[] = {"0,1,0, 0,0,1, 1,0,0", "-1,0,0, 0,0,1, 0,1,0", "0,-1,0, 0,0,1, -1,0,0"};
  std::ostringstream s;
  s << R"({"cameras": [)";
  for (int i = 0; i < 3; ++i)
    s << (i ? "," : "") << R"({"id": "c)" << i << R"(", "image": "img.png", "width": 64, "height": 48, "center": [)"
      << i << R"(, 0, 0], "rotation": [)" << rotations[i] << R"(], "focal": [50, 50], "principal": [32, 24]})";
  s << "]}";
  return s.str();
}

class SceneUp : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv_scene_up_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // A real 1x1 PNG (the loader checks the image's header).
    const unsigned char png[] = {0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48,
                                 0x44, 0x52, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x02, 0x00, 0x00,
                                 0x00, 0x90, 0x77, 0x53, 0xde, 0x00, 0x00, 0x00, 0x0c, 0x49, 0x44, 0x41, 0x54, 0x08,
                                 0xd7, 0x63, 0xf8, 0xcf, 0xc0, 0x00, 0x00, 0x03, 0x01, 0x01, 0x00, 0x18, 0xdd, 0x8d,
                                 0xb0, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
    std::ofstream((dir_ / "img.png").string(), std::ios::binary).write(reinterpret_cast<const char*>(png), sizeof png);
    std::ofstream((dir_ / "cameras.json").string()) << camerasJson();
  }
  void TearDown() override { fs::remove_all(dir_); }
  Scene load(const std::string& sceneJson, Diagnostics& diag) {
    std::ofstream((dir_ / "scene.json").string()) << sceneJson;
    return loadScene((dir_ / "scene.json").string(), diag);
  }
  fs::path dir_;
};

TEST_F(SceneUp, WithoutCrsOrUpTheCamerasGiveIt) {
  Diagnostics diag;
  const Scene scene = load(R"({"cameras": {"path": "cameras.json"}})", diag);
  ASSERT_EQ(scene.photos.size(), 3u);
  EXPECT_NEAR(glm::length(scene.up - glm::dvec3(0, 0, -1)), 0.0, 1e-12);
  EXPECT_NE(upOrigin(scene).find("inferred from the 3 cameras"), std::string::npos) << upOrigin(scene);
  bool said = false;
  for (const std::string& w : diag.warnings) said |= w.find("inferred from the 3 cameras") != std::string::npos;
  EXPECT_TRUE(said) << "an up 180 degrees from z is said when the scene loads";
}

TEST_F(SceneUp, ADeclaredUpIsKeptAndNamedWhenTheCamerasDisagree) {
  Diagnostics diag;
  const Scene scene = load(R"({"up": [0, 0, 1], "cameras": {"path": "cameras.json"}})", diag);
  EXPECT_EQ(scene.up, glm::dvec3(0, 0, 1));
  bool named = false;
  for (const std::string& w : diag.warnings)
    named |= w.find("up: (0.000, 0.000, 1.000) is 180 degrees from the cameras' mean image up") != std::string::npos;
  EXPECT_TRUE(named);
  Diagnostics agreeing;
  const Scene minusZ = load(R"({"up": [0, 0, -1], "cameras": {"path": "cameras.json"}})", agreeing);
  EXPECT_EQ(minusZ.up, glm::dvec3(0, 0, -1));
  EXPECT_TRUE(agreeing.warnings.empty());
}

TEST(CameraUp, IsTheMeanOfTheImageUpVectors) {
  std::vector<Photo> photos(2);
  photos[0].camera = lookAtCamera("a", {0, 0, 0}, {1, 0, 0}, 10, 10, 10);             // up z
  photos[1].camera = lookAtCamera("b", {0, 0, 0}, {0, 1, 0}, 10, 10, 10, {1, 0, 0});  // up x
  const CameraUp u = cameraUp(photos);
  EXPECT_NEAR(glm::length(u.up - glm::normalize(glm::dvec3(1, 0, 1))), 0.0, 1e-12);
  EXPECT_NEAR(u.agreement, std::sqrt(0.5), 1e-12);
  EXPECT_EQ(u.cameras, 2u);
}

}  // namespace
}  // namespace hv
