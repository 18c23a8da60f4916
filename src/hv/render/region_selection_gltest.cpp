// Region selection on the GPU (docs/design.md, steps 1 and 5): a wide view over two streets far
// apart, each photographed by its own cameras, is textured on both streets, each by its own
// photographs; the papers' global selection textures only the street nearer to the view.
#include "hv/render/renderer.h"

#include "hv/image/native/png_write.h"
#include "hv/render/testing/gl_test_support.h"

#include <gtest/gtest.h>

namespace hv::render {
namespace {

using testing::glContext;
using testing::kStreetOrigin;

class RegionSelectionGlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    glContext();
    gpu::clearGlErrors();
    dir_ = testing::makeTempDir("region");
    const glm::dvec3 o = kStreetOrigin;
    scene_.origin = o;
    // Ground 800 x 300 m; street A at x = 0, street B at x = 500, six photographs each looking
    // along the street (+y) and down at the ground: A's red, B's green.
    scene_.terrain.positions = {o + glm::dvec3(-150, -50, 0), o + glm::dvec3(650, -50, 0), o + glm::dvec3(650, 250, 0),
                                o + glm::dvec3(-150, 250, 0)};
    scene_.terrain.triangles = {{0, 1, 2}, {0, 2, 3}};
    for (int s = 0; s < 2; ++s)
      for (int i = 0; i < 6; ++i) {
        Photo p;
        const glm::dvec3 c = o + glm::dvec3(500.0 * s, 20.0 * i, 6.0);
        p.camera = testing::lookAt(std::string(s ? "b" : "a") + std::to_string(i), c, c + glm::dvec3(0, 30, -6), 160,
                                   120, 110);
        p.imagePath = dir_ + "/" + p.camera.id + ".png";
        writePng(p.imagePath, s ? testing::solidImage(160, 120, 0, 255, 0) : testing::solidImage(160, 120, 255, 0, 0));
        scene_.photos.push_back(p);
      }
    // Above, south of the streets and nearer to A; both streets in the picture.
    view_ = testing::lookAt("overview", o + glm::dvec3(100, -400, 300), o + glm::dvec3(250, 100, 0), 320, 200, 200);
  }
  void TearDown() override { EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR)) << "a GL error was left behind"; }

  // Pixels painted red (street A's photographs) and green (street B's).
  std::pair<int, int> redGreen(ibr::Selection selection, Image8* picture = nullptr, Binding binding = Binding::Array) {
    Diagnostics diag;
    RenderSettings settings;
    settings.binding = binding;
    settings.blend.k = 4;
    settings.blend.selection = selection;
    settings.depthSize = 256;
    Renderer renderer(scene_, settings, diag);
    const RenderOutput out = renderer.render(view_);
    EXPECT_TRUE(diag.ok());
    int red = 0, green = 0;
    for (int y = 0; y < view_.height; ++y)
      for (int x = 0; x < view_.width; ++x) {
        const std::uint8_t* p = out.rgba.px(x, y);
        if (p[3] == 0) continue;
        red += p[0] > 200 && p[1] < 50;
        green += p[1] > 200 && p[0] < 50;
      }
    if (picture) *picture = out.rgba;
    return {red, green};
  }

  std::string dir_;
  Scene scene_;
  Camera view_;
};

TEST_F(RegionSelectionGlTest, OneWideViewTexturesEachStreetByItsOwnPhotographs) {
  Image8 picture;
  const auto [redRegion, greenRegion] = redGreen(ibr::Selection::Region, &picture);
  const auto [redGlobal, greenGlobal] = redGreen(ibr::Selection::Global);
  // Global: the 4 (+1) nearest to the view are all in street A: B stays black.
  EXPECT_GT(redGlobal, 500);
  EXPECT_EQ(greenGlobal, 0);
  // Region: both streets, each in its own colour; A as textured as with the global selection.
  EXPECT_GT(greenRegion, 500) << "street B untextured";
  EXPECT_GE(redRegion, redGlobal);
  // Each street by its own photographs: red only left of the middle of the picture, green only
  // right of it (A at x = 0 is on the left of a view looking north).
  int redRight = 0, greenLeft = 0;
  for (int y = 0; y < picture.height; ++y)
    for (int x = 0; x < picture.width; ++x) {
      const std::uint8_t* p = picture.px(x, y);
      if (p[3] == 0) continue;
      redRight += x > picture.width / 2 && p[0] > 200 && p[1] < 50;
      greenLeft += x < picture.width / 2 && p[1] > 200 && p[0] < 50;
    }
  EXPECT_EQ(redRight, 0);
  EXPECT_EQ(greenLeft, 0);
}

// The naive binding (a sampler pair per image) runs the same per-pixel blend over its candidates
// (capped by its texture units: here all twelve photographs fit either way).
TEST_F(RegionSelectionGlTest, NaiveBindingBlendsPerPixelToo) {
  Image8 array, naive;
  const auto [redArray, greenArray] = redGreen(ibr::Selection::Region, &array);
  const auto [redNaive, greenNaive] = redGreen(ibr::Selection::Region, &naive, Binding::Naive);
  EXPECT_GT(greenNaive, 500);
  EXPECT_EQ(redNaive, redArray);
  EXPECT_EQ(greenNaive, greenArray);
  int differ = 0;
  for (size_t i = 0; i < array.data.size(); ++i) differ += std::abs(int(array.data[i]) - int(naive.data[i])) > 2;
  EXPECT_EQ(differ, 0);
}

}  // namespace
}  // namespace hv::render
