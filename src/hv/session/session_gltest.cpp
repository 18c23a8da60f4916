// GL test of hv::app::makeRenderer, the renderer every command and the viewer builds for a scene:
// the photographs scene.json gives edited layers (docs/layers.md) are textured with them, also
// when the renderer is built again after a photograph's camera changed (the viewer's pose mode);
// a layers file that cannot be used is named and the photograph renders as itself.
#include "hv/session/make_renderer.h"

#include "hv/image/native/png_write.h"
#include "hv/layers/native/layer_export.h"
#include "hv/layers/native/openraster.h"
#include "hv/render/testing/gl_test_support.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace hv::app {
namespace {

namespace fs = std::filesystem;
using testing::kStreetOrigin;

class MakeRendererGlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    testing::glContext();
    dir_ = testing::makeTempDir("session-layers");
    scene_ = testing::streetScene();
    const glm::dvec3 o = kStreetOrigin;
    // Photograph "a" sees the near building in front of the far one: two visibility layers.
    Photo p;
    p.camera = testing::lookAt("a", o + glm::dvec3(0, -12, 2), o + glm::dvec3(0, 30, 8), 96, 72, 80);
    p.imagePath = dir_ + "/a.png";
    writePng(p.imagePath, testing::patternImage(96, 72, 1));
    scene_.photos.push_back(p);
    scene_.path = dir_ + "/scene.json";
    settings_.depthSize = 256;
    settings_.decodeThreads = 0;
  }

  // scene.json names `file` as photograph a's layers.
  void nameLayers(const std::string& file) {
    std::ofstream(scene_.path) << "{\"layers\": {\"a\": \"" << file << "\"}}\n";
  }
  // Photograph a's layers as exported (unedited), at its size.
  void exportLayers(const std::string& file) {
    Diagnostics diag;
    const layers::LayerExport ex = layers::exportLayers(scene_, 0, layers::LayerExportSettings{}, diag);
    ASSERT_TRUE(diag.errors.empty()) << diag.errors.front();
    ASSERT_GE(ex.visibility.layers.size(), 2u) << "the near building hides none of the far one";
    layers::writeOpenRaster(dir_ + "/" + file, ex.document);
  }
  // The image parameters of photograph a's sub-images (visibility layer >= 1) in a frame of its own view.
  static std::size_t subImagesDrawn(render::Renderer& r, const Camera& view) {
    r.render(view);
    std::size_t n = 0;
    for (const ibr::ImageParams& p : r.lastImageParams()) n += p.photo == 0 && p.layer >= 1;
    return n;
  }

  std::string dir_;
  Scene scene_;
  render::RenderSettings settings_;
};

TEST_F(MakeRendererGlTest, TexturesAPhotographWithItsLayersAlsoAfterItsCameraChanged) {
  exportLayers("a.ora");
  nameLayers("a.ora");
  Diagnostics diag;
  std::unique_ptr<render::Renderer> r = makeRenderer(scene_, settings_, diag);
  EXPECT_TRUE(diag.errors.empty()) << diag.errors.front();
  const Camera view = scene_.photos[0].camera;
  EXPECT_GE(subImagesDrawn(*r, view), 2u);
  EXPECT_GE(r->stats().depthMapsUploaded, 2);
  // A renderer made directly has none of the layers (what the viewer's rebuilds were).
  render::Renderer plain(scene_, settings_, diag);
  EXPECT_EQ(subImagesDrawn(plain, view), 0u);
  EXPECT_EQ(plain.stats().depthMapsUploaded, 0);

  // Pose mode moves the photograph (same size) and builds the renderer again: the layers are
  // peeled again for the camera as it is now.
  r.reset();
  scene_.photos[0].camera =
      testing::lookAt("a", kStreetOrigin + glm::dvec3(1, -12.5, 2.2), kStreetOrigin + glm::dvec3(1, 30, 8), 96, 72, 80);
  Diagnostics again;
  r = makeRenderer(scene_, settings_, again);
  EXPECT_TRUE(again.errors.empty()) << again.errors.front();
  EXPECT_GE(subImagesDrawn(*r, scene_.photos[0].camera), 2u);
  EXPECT_GE(r->stats().depthMapsUploaded, 2);
}

TEST_F(MakeRendererGlTest, ABrokenLayersFileIsNamedAndThePhotographRendersAsItself) {
  std::ofstream(dir_ + "/bad.ora") << "not a zip";
  nameLayers("bad.ora");
  Diagnostics diag;
  std::unique_ptr<render::Renderer> r = makeRenderer(scene_, settings_, diag);
  ASSERT_EQ(diag.errors.size(), 1u);
  EXPECT_NE(diag.errors[0].find("bad.ora"), std::string::npos) << diag.errors[0];
  EXPECT_NE(diag.errors[0].find("layers of photograph 'a' left out"), std::string::npos) << diag.errors[0];
  const Camera view = scene_.photos[0].camera;
  EXPECT_EQ(subImagesDrawn(*r, view), 0u);
  bool drawn = false;
  for (const ibr::ImageParams& p : r->lastImageParams()) drawn |= p.photo == 0 && p.layer == 0;
  EXPECT_TRUE(drawn) << "the photograph is not drawn as itself";
}

}  // namespace
}  // namespace hv::app
