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
