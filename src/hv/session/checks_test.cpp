#include "hv/session/checks.h"

#include "hv/image/native/png_write.h"

#include <CLI/CLI.hpp>
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>

namespace hv::app {
namespace {

namespace fs = std::filesystem;

class Checks : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv_checks_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string png(const std::string& name, int w, int h, int channels = 3) {
    const std::string p = (dir_ / name).string();
    writePng(p, Image8(w, h, channels, 128));
    return p;
  }
  std::string text(const std::string& name, const std::string& content) {
    const std::string p = (dir_ / name).string();
    std::ofstream(p) << content;
    return p;
  }
  Photo photo(const std::string& id, const std::string& image, int w, int h) {
    Photo p;
    p.camera.id = id;
    p.camera.width = w;
    p.camera.height = h;
    p.imagePath = image;
    return p;
  }
  fs::path dir_;
};

std::string validate(const CLI::Validator& v, std::string text) { return v(text); }

TEST_F(Checks, ProbesHeadersAndRefusesWhatIsNotAnImage) {
  const ImageHeader h = probeImageFile(png("a.png", 40, 30));
  EXPECT_EQ(h.width, 40);
  EXPECT_EQ(h.height, 30);
  EXPECT_EQ(h.channels, 3);
  EXPECT_GT(h.decodeBytes, size_t(40 * 30 * 3));
  try {
    probeImageFile(text("passwd", "root:x:0:0:root:/root:/bin/bash\n"));
    FAIL() << "a text file passed as an image";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("passwd"), std::string::npos) << e.what();
  }
  EXPECT_THROW(probeImageFile((dir_ / "missing.png").string()), InputError);
  EXPECT_THROW(probeImageFile(dir_.string()), InputError);  // a directory
}

TEST_F(Checks, AFifoIsRefusedWithoutBlocking) {
  const std::string fifo = (dir_ / "photo.jpg").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    probeImageFile(fifo);
    FAIL() << "a FIFO passed as an image";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0);
}

TEST_F(Checks, DecodesUnderTheCapOnly) {
  const std::string p = png("b.png", 400, 300);
  EXPECT_EQ(decodeImageCapped(p, std::size_t(64) << 20).width, 400);
  try {
    decodeImageCapped(p, 100000);
    FAIL() << "decoded beyond the cap";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("400x300"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("limit"), std::string::npos) << e.what();
  }
}

TEST_F(Checks, SceneReportNamesWhatWouldBeLeftOut) {
  Scene s;
  s.path = (dir_ / "scene.json").string();
  s.photos.push_back(photo("good", png("good.png", 64, 48), 64, 48));
  Photo masked = photo("masked", png("m.png", 64, 48), 64, 48);
  masked.maskPath = png("m-mask.png", 32, 24, 1);  // same aspect, other size: resampled (a warning)
  s.photos.push_back(masked);
  Photo badMask = photo("bad-mask", png("bm.png", 64, 48), 64, 48);
  badMask.maskPath = png("bm-mask.png", 50, 50, 1);  // another aspect ratio: left out
  s.photos.push_back(badMask);
  s.photos.push_back(photo("not-an-image", text("x.jpg", "hello"), 64, 48));
  s.photos.push_back(photo("wrong-aspect", png("w.png", 48, 48), 64, 48));
  s.photos.push_back(photo("good", png("good2.png", 64, 48), 64, 48));  // a duplicate id
  s.photos.back().date = "last spring";
  Diagnostics load;
  load.errors.push_back("cameras.json: camera 'broken': rotation: not orthonormal (camera left out)");
  for (bool deep : {false, true}) {
    CheckOptions o;
    o.deep = deep;
    int calls = 0;
    o.progress = [&](int, int total) {
      ++calls;
      EXPECT_EQ(total, 6);
    };
    const CheckReport r = checkScene(s, load, o);
    EXPECT_EQ(calls, 6);
    EXPECT_EQ(r.photographs, 6);
    EXPECT_EQ(r.masks, 2);
    EXPECT_EQ(r.problems(), 4u) << r.text();  // broken, bad-mask, not-an-image, wrong-aspect
    const std::string t = r.text();
    EXPECT_NE(t.find("camera 'broken'"), std::string::npos) << t;
    EXPECT_NE(t.find("camera 'bad-mask': mask"), std::string::npos) << t;
    EXPECT_NE(t.find("x.jpg"), std::string::npos) << t;
    EXPECT_NE(t.find("48x48, expected the camera's 64x48"), std::string::npos) << t;
    EXPECT_NE(t.find("camera 'good': duplicate id"), std::string::npos) << t;
    EXPECT_NE(t.find("32x24"), std::string::npos) << t;  // the resampled mask, a warning
    EXPECT_NE(t.find("last spring"), std::string::npos) << t;
    EXPECT_NE(t.find("masks\n"), std::string::npos) << t;  // grouped by kind
    const nlohmann::json j = r.json();
    EXPECT_EQ(j["problems"], 4);
    EXPECT_EQ(j["items"].size(), r.items.size());
  }
}

// --sigma is checked by the settings schema (render/settings_schema.cpp: above 0, at most 1e7).
TEST(CheckOptionValues, Counts) {
  const std::string k0 = validate(positiveCount(), "0");
  EXPECT_NE(k0.find("expected a whole number of at least 1, got '0'"), std::string::npos) << k0;
  EXPECT_LT(k0.size(), 80u);  // not CLI11's 309-digit range
  EXPECT_NE(validate(positiveCount(), "2.5"), "");
  EXPECT_EQ(validate(positiveCount(), "8"), "");
}

TEST(CheckOptionValues, ViewSizes) {
  Camera c;
  c.width = 640;
  c.height = 480;
  EXPECT_EQ(viewSizeProblem(c, 16384), "");
  c.width = 20000;
  c.height = 15000;
  const std::string big = viewSizeProblem(c, 16384);
  EXPECT_NE(big.find("20000x15000"), std::string::npos) << big;
  EXPECT_NE(big.find("MAX_TEXTURE_SIZE (16384)"), std::string::npos) << big;
  c.width = 12000;
  c.height = 9000;  // under MAX_TEXTURE_SIZE, over the pixel budget
  const std::string many = viewSizeProblem(c, 16384);
  EXPECT_NE(many.find("megapixels"), std::string::npos) << many;
  EXPECT_NE(many.find(std::to_string(kMaxViewPixels / 1000000)), std::string::npos) << many;
}

}  // namespace
}  // namespace hv::app
