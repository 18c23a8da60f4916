// Renderer::replaceImage on llvmpipe: a photograph shown as a small image (the page's IIIF
// preview) and then given its full image draws what a photograph loaded with the full image from
// the start draws; the frame before the replacement is textured by the small image (against the
// CPU slice of it); a full image that cannot be read keeps the small one, named.
#include "hv/render/renderer.h"

#include "hv/ibr/slice_image.h"
#include "hv/image/native/png_write.h"
#include "hv/render/testing/gl_test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

namespace hv::render {
namespace {

using testing::kStreetOrigin;

class ReplaceImageGlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    testing::glContext();
    gpu::clearGlErrors();
    dir_ = testing::makeTempDir("replace-image");
    scene_ = testing::streetScene();
    const glm::dvec3 o = kStreetOrigin;
    camera_ = testing::lookAt("a", o + glm::dvec3(-6, -12, 2), o + glm::dvec3(0, 30, 8), 160, 120, 130);
    full_ = testing::patternImage(160, 120, 1);
    // The preview: the full image averaged over 4 x 4 blocks (a server's small size).
    preview_ = Image8(40, 30, 3);
    for (int y = 0; y < 30; ++y)
      for (int x = 0; x < 40; ++x)
        for (int c = 0; c < 3; ++c) {
          int sum = 0;
          for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) sum += full_.at(4 * x + i, 4 * y + j, c);
          preview_.at(x, y, c) = std::uint8_t((sum + 8) / 16);
        }
    writePng(fullPath(), full_);
    writePng(previewPath(), preview_);
    Photo p;
    p.camera = camera_;
    p.imagePath = previewPath();
    scene_.photos.push_back(p);
    settings_.blend.k = 1;
    settings_.depthSize = 512;
    settings_.blend.mipmaps = true;
  }
  void TearDown() override { EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR)) << "a GL error was left behind"; }

  std::string fullPath() const { return dir_ + "/a.png"; }
  std::string previewPath() const { return dir_ + "/a-40.png"; }
  // The photograph's own view, and a minified one (its mip levels).
  std::vector<Camera> views() const {
    const glm::dvec3 o = kStreetOrigin;
    return {camera_, testing::lookAt("far", o + glm::dvec3(-6, -12, 2), o + glm::dvec3(0, 30, 8), 37, 28, 130.0 / 4.3)};
  }
  // The largest channel difference between two frames, and the pixels covered in both.
  static int maxDiff(const Image8& a, const Image8& b, int* covered = nullptr) {
    int worst = 0, n = 0;
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x) {
        if (a.px(x, y)[3] != b.px(x, y)[3]) return 255;
        if (a.px(x, y)[3] == 0) continue;
        ++n;
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(a.px(x, y)[c]) - int(b.px(x, y)[c])));
      }
    if (covered) *covered = n;
    return worst;
  }
  // The view from the photograph's camera at its size samples the slice at its texels (the slot is
  // the camera's size): the covered pixels against the CPU slice made from `image`, within 2/255;
  // returns how many were compared.
  int compareWithSlice(const Image8& frame, const Image8& image, ibr::SliceSize slice) const {
    const Image8 s = ibr::makeSliceImage(camera_, image, Image8{}, slice, camera_.id);
    int compared = 0, worst = 0;
    for (int y = 2; y < frame.height - 2; ++y)
      for (int x = 2; x < frame.width - 2; ++x) {
        if (frame.px(x, y)[3] == 0) continue;
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(frame.px(x, y)[c]) - int(s.px(x, y)[c])));
        ++compared;
      }
    EXPECT_LE(worst, 2) << "over " << compared << " pixels";
    return compared;
  }

  std::string dir_;
  Scene scene_;
  Camera camera_;
  Image8 full_, preview_;
  RenderSettings settings_;
};

TEST_F(ReplaceImageGlTest, ReplacedImageDrawsAsTheLargerImageFromTheStart) {
  Diagnostics diag;
  Renderer replaced(scene_, settings_, diag);
  std::vector<Image8> previewFrames;
  for (const Camera& v : views()) previewFrames.push_back(replaced.render(v).rgba);
  ASSERT_TRUE(diag.ok());
  const int slot = replaced.slotOf(0);
  const int depthMaps = replaced.stats().depthMapsRendered, loaded = replaced.stats().imagesLoaded;
  ASSERT_GE(slot, 0);
  EXPECT_EQ(depthMaps, 1);
  // The frame before the replacement is textured by the preview.
  EXPECT_GT(compareWithSlice(previewFrames[0], preview_, replaced.sliceSize()), 160 * 120 / 2);

  scene_.photos[0].imagePath = fullPath();
  replaced.replaceImage(0);
  std::vector<Image8> after;
  for (const Camera& v : views()) after.push_back(replaced.render(v).rgba);
  EXPECT_TRUE(diag.ok());
  EXPECT_TRUE(replaced.converged());
  // The same slot and depth map; not a new photograph loaded.
  EXPECT_EQ(replaced.slotOf(0), slot);
  EXPECT_EQ(replaced.stats().depthMapsRendered, depthMaps);
  EXPECT_EQ(replaced.stats().imagesLoaded, loaded);

  Diagnostics diagFresh;
  Renderer fresh(scene_, settings_, diagFresh);
  for (size_t i = 0; i < views().size(); ++i) {
    const Image8 f = fresh.render(views()[i]).rgba;
    int covered = 0;
    EXPECT_LE(maxDiff(after[i], f, &covered), 1) << views()[i].id;
    EXPECT_GT(covered, f.width * f.height / 2) << views()[i].id;
    // And the preview's own view was not the full image's (the preview is blurred).
    if (i == 0) EXPECT_GE(maxDiff(previewFrames[i], f), 8);
  }
  EXPECT_GT(compareWithSlice(after[0], full_, replaced.sliceSize()), 160 * 120 / 2);
}

TEST_F(ReplaceImageGlTest, ProgressiveFramesShowTheSmallImageUntilTheLargerOneIsIn) {
  settings_.decodeThreads = 1;
  Diagnostics diag;
  Renderer r(scene_, settings_, diag);
  const Camera view = views()[0];
  r.render(view);  // batch: resident with its depth map
  scene_.photos[0].imagePath = fullPath();
  r.replaceImage(0);
  // Not converged until the decode is in (a decoding thread: the frames go on meanwhile); then
  // the full image.
  Image8 last;
  int frames = 0;
  do {
    last = r.render(view, false, FrameMode::Progressive).rgba;
  } while (!r.converged() && ++frames < 2000);
  ASSERT_TRUE(r.converged());
  EXPECT_TRUE(diag.ok());
  EXPECT_GT(compareWithSlice(last, full_, r.sliceSize()), 160 * 120 / 2);
}

TEST_F(ReplaceImageGlTest, LargerImageThatFailsKeepsTheSmallOneNamed) {
  Diagnostics diag;
  Renderer r(scene_, settings_, diag);
  const Camera view = views()[0];
  const Image8 before = r.render(view).rgba;
  scene_.photos[0].imagePath = dir_ + "/missing.png";
  r.replaceImage(0);
  const Image8 after = r.render(view).rgba;
  ASSERT_EQ(diag.errors.size(), 1u);
  EXPECT_NE(diag.errors[0].find("missing.png"), std::string::npos) << diag.errors[0];
  EXPECT_NE(diag.errors[0].find("camera 'a'"), std::string::npos) << diag.errors[0];
  EXPECT_NE(diag.errors[0].find("keeps the smaller image"), std::string::npos) << diag.errors[0];
  EXPECT_EQ(r.photoState(0), PhotoState::Ready);
  EXPECT_TRUE(r.converged());
  EXPECT_EQ(maxDiff(before, after), 0);
  EXPECT_THROW(r.replaceImage(1), std::invalid_argument);
}

}  // namespace
}  // namespace hv::render
