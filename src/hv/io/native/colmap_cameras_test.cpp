#include "hv/io/native/colmap_cameras.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace hv {
namespace {

class ColmapTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("hv-colmap-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    std::ofstream(dir_ / "cameras.txt") << "# Camera list with one line of data per camera:\n"
                                           "1 SIMPLE_PINHOLE 640 480 500 320 240\n"
                                           "2 RADIAL 640 480 500 320 240 0.1 0.01\n"
                                           "3 FULL_OPENCV 640 480 500 500 320 240 0 0 0 0 0 0 0 0\n"
                                           "5 OPENCV 640 480 500 490 320 240 0.1 -0.02 0.001 0.002\n";
    const double h = std::sqrt(0.5);  // cos 45 deg = sin 45 deg: a 90 degree turn about z
    std::ofstream(dir_ / "images.txt") << "# Image list with two lines of data per image:\n"
                                          "1 1 0 0 0 0 0 5 1 a.jpg\n"
                                          "420 290 -1\n"
                                          "2 " << h << " 0 0 " << h << " 0 0 4 2 sub/b.jpg\n"
                                          "\n"
                                          "3 1 0 0 0 0 0 5 3 c.jpg\n"
                                          "\n"
                                          "4 0 0 0 0 0 0 5 1 d.jpg\n"
                                          "\n"
                                          "5 1 0 0 0 0 0 5 5 e.jpg\n"
                                          "\n";
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

TEST_F(ColmapTest, ReadsPosesAndModelsAgainstHandValues) {
  Diagnostics diag;
  const auto photos = readColmapModel(dir_.string(), "/photos", diag, false);
  ASSERT_EQ(photos.size(), 3u);
  // Camera 3 (FULL_OPENCV) is unsupported; image 3 uses it; image 4 has a zero quaternion.
  ASSERT_EQ(diag.errors.size(), 3u);
  EXPECT_NE(diag.errors[0].find("OPENCV"), std::string::npos) << diag.errors[0];
  EXPECT_NE(diag.errors[1].find("CAMERA_ID 3"), std::string::npos) << diag.errors[1];
  EXPECT_NE(diag.errors[2].find("quaternion"), std::string::npos) << diag.errors[2];
  EXPECT_NE(diag.errors[2].find("images.txt:8"), std::string::npos) << diag.errors[2];

  const glm::dvec3 X(1.0, 0.5, 0.0);
  // Image 1: identity rotation, T = (0, 0, 5): x_cam = (1, 0.5, 5), pixel = 500 (0.2, 0.1) + (320, 240).
  const Camera& a = photos[0].camera;
  EXPECT_EQ(a.id, "a");
  EXPECT_EQ(photos[0].imagePath, "/photos/a.jpg");
  EXPECT_NEAR(glm::length(a.center - glm::dvec3(0, 0, -5)), 0.0, 1e-12);
  EXPECT_NEAR(a.project(X).pxDistorted.x, 420.0, 1e-9);
  EXPECT_NEAR(a.project(X).pxDistorted.y, 290.0, 1e-9);

  // Image 2: R = Rz(90 deg): (x, y, z) -> (-y, x, z); T = (0, 0, 4): x_cam = (-0.5, 1, 4).
  // COLMAP RADIAL: u = (-0.125, 0.25), u_d = u (1 + k1 r2 + k2 r2^2), pixel = f u_d + c.
  const Camera& b = photos[1].camera;
  EXPECT_EQ(b.id, "b");
  EXPECT_NEAR(glm::length(b.center - glm::dvec3(0, 0, -4)), 0.0, 1e-12);
  const double ux = -0.125, uy = 0.25, r2 = ux * ux + uy * uy, g = 1.0 + 0.1 * r2 + 0.01 * r2 * r2;
  EXPECT_NEAR(b.project(X).pxDistorted.x, 500.0 * ux * g + 320.0, 1e-9);
  EXPECT_NEAR(b.project(X).pxDistorted.y, 500.0 * uy * g + 240.0, 1e-9);
}

TEST_F(ColmapTest, OpenCvModelHasTangentialTerms) {
  Diagnostics diag;
  const auto photos = readColmapModel(dir_.string(), "/photos", diag, false);
  ASSERT_EQ(photos.size(), 3u);
  const Camera& e = photos[2].camera;
  ASSERT_EQ(e.id, "e");
  // x_cam = (1, 0.5, 5): u = (0.2, 0.1); OpenCV: u_d = u (1 + k1 r2 + k2 r2^2) + tangential.
  const double x = 0.2, y = 0.1, r2 = x * x + y * y, radial = 1 + 0.1 * r2 - 0.02 * r2 * r2;
  const double xd = x * radial + 2 * 0.001 * x * y + 0.002 * (r2 + 2 * x * x);
  const double yd = y * radial + 0.001 * (r2 + 2 * y * y) + 2 * 0.002 * x * y;
  const Projection p = e.project({1.0, 0.5, 0.0});
  EXPECT_NEAR(p.pxDistorted.x, 320 + 500 * xd, 1e-9);
  EXPECT_NEAR(p.pxDistorted.y, 240 + 490 * yd, 1e-9);
}

TEST(Colmap, DuplicateIdsAndAbsurdSizesAreNamedAndTheFirstKept) {
  const auto dir = std::filesystem::temp_directory_path() / ("hv-colmap-dup-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "cameras.txt") << "1 SIMPLE_PINHOLE 640 480 500 320 240\n"
                                        "1 SIMPLE_PINHOLE 320 240 250 160 120\n"
                                        "2 SIMPLE_PINHOLE 1000000000 480 500 320 240\n";
  std::ofstream(dir / "images.txt") << "1 1 0 0 0 0 0 5 1 a.jpg\n\n"
                                       "1 1 0 0 0 1 0 5 1 b.jpg\n\n"
                                       "2 1 0 0 0 2 0 5 1 sub/a.jpg\n\n"
                                       "3 1 0 0 0 3 0 5 2 c.jpg\n\n";
  Diagnostics diag;
  const auto photos = readColmapModel(dir.string(), "/photos", diag, false);
  std::string all;
  for (const std::string& e : diag.errors) all += e + "\n";
  ASSERT_EQ(photos.size(), 1u) << all;
  EXPECT_EQ(photos[0].camera.id, "a");
  EXPECT_EQ(photos[0].camera.width, 640);  // the first camera 1
  ASSERT_EQ(diag.errors.size(), 5u) << all;
  EXPECT_NE(diag.errors[0].find("cameras.txt:2"), std::string::npos) << all;
  EXPECT_NE(diag.errors[0].find("duplicate"), std::string::npos) << all;
  EXPECT_NE(diag.errors[1].find("65536"), std::string::npos) << all;
  EXPECT_NE(diag.errors[2].find("IMAGE_ID 1: duplicate"), std::string::npos) << all;
  EXPECT_NE(diag.errors[3].find("'a'"), std::string::npos) << all;  // sub/a.jpg: the same id
  EXPECT_NE(diag.errors[3].find("duplicate"), std::string::npos) << all;
  EXPECT_NE(diag.errors[4].find("CAMERA_ID 2"), std::string::npos) << all;  // its camera was refused
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hv
