// Real street panoramas (../shared/data/paris-stereopolis, iTowns oriented images, no geometry):
// rendered from the rig's own cameras on the background sphere, each camera reproduces its
// photograph; the gaps and overlaps between neighbouring cameras of one panorama are reported.
// How far apart two cameras put the same content (the calibration itself leaves seams of 10-25 px;
// a bound would not tell a right model from a wrong one, so none is asserted) is measured on the
// CPU by hv/eval/seams.h (ParisSeams in src/hv/eval/paris_seams_test.cpp, docs/evaluation.md).
#include "hv/eval/metrics.h"
#include "hv/image/image.h"
#include "hv/io/native/scene_loader.h"
#include "hv/render/renderer.h"
#include "hv/render/testing/gl_test_support.h"
#include "hv/testing/data_dir.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cmath>
#include <filesystem>

namespace hv::render {
namespace {

constexpr const char* kPano = "0000243";

class PanoramaGlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string dir = hv::testing::dataset("paris-stereopolis");
    if (dir.empty()) HV_SKIP_WITHOUT_DATA(std::string("paris-stereopolis not found under ") + hv::testing::dataDir() + " (HISTOVIEW_DATA)");
    testing::glContext();
    Diagnostics diag;
    scene_ = loadScene(dir + "/scene.json", diag);
    ASSERT_TRUE(diag.ok()) << (diag.errors.empty() ? std::string() : diag.errors[0]);
    for (size_t i = 0; i < scene_.photos.size(); ++i)
      if (scene_.photos[i].camera.id.ends_with(kPano)) rig_.push_back(int(i));
    ASSERT_EQ(rig_.size(), 5u);
  }

  // Renders `view` from photograph `only` alone (every other one excluded).
  Image8 renderFrom(int only, const Camera& view, double sphere) {
    RenderSettings s;
    s.blend.k = 1;
    s.backgroundSphere = sphere;
    s.depthSize = 256;
    s.maxSliceSize = 512;  // photographs resampled once, as the reference is
    for (size_t i = 0; i < scene_.photos.size(); ++i)
      if (int(i) != only) s.blend.exclude.push_back(scene_.photos[i].camera.id);
    Diagnostics diag;
    Renderer r(scene_, s, diag);
    return r.render(view).rgba;
  }

  Scene scene_;
  std::vector<int> rig_;
};

TEST_F(PanoramaGlTest, EachCameraReproducesItsPhotographOnTheSphere) {
  for (int i : rig_) {
    const Photo& photo = scene_.photos[size_t(i)];
    const Camera view = photo.camera.resized(512, 512);
    for (double radius : {10.0, 1000.0}) {
      const Image8 out = renderFrom(i, view, radius);
      const Image8 truth = resizeImage(readImage(photo.imagePath, 3), 512, 512);
      std::vector<std::uint8_t> covered(size_t(out.width) * out.height);
      for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) covered[size_t(y) * out.width + x] = out.px(x, y)[3] > 0;
      const eval::Scores sc = eval::compareImages(out, truth, covered);
      const double coverage = double(sc.scoredPixels) / double(covered.size());
      std::printf("self-view %s radius %6.0f: PSNR %.2f dB, coverage %.1f %%\n", photo.camera.id.c_str(), radius,
                  sc.psnr, 100.0 * coverage);
      // The photograph through its own camera: only resampling differs (512 from 2048 px).
      EXPECT_GT(sc.psnr, 35.0) << photo.camera.id;
      EXPECT_GT(coverage, 0.95) << photo.camera.id;
    }
  }
}

// The seam between two cameras of the rig, along the great circle through both axes: a view at
// the rig's centre looks half-way between them with both axes on its middle row; on the rows
// around it, the columns that neither photograph covers (a gap) and that both cover (an overlap).
TEST_F(PanoramaGlTest, SeamsBetweenNeighbouringCamerasAreReported) {
  int pairs = 0;
  for (size_t a = 0; a < rig_.size(); ++a)
    for (size_t b = a + 1; b < rig_.size(); ++b) {
      const Camera& ca = scene_.photos[size_t(rig_[a])].camera;
      const Camera& cb = scene_.photos[size_t(rig_[b])].camera;
      const glm::dvec3 za = glm::transpose(ca.camFromWorld)[2], zb = glm::transpose(cb.camFromWorld)[2];
      if (glm::dot(za, zb) < -0.5) continue;  // opposite cameras: no common boundary
      const glm::dvec3 centre = 0.5 * (ca.center + cb.center);
      const double viewFocal = 0.25 * ca.focal.x;  // a quarter of the photographs' resolution
      const Camera view = lookAtCamera("seam", centre, centre + glm::normalize(za + zb), 512, 256, viewFocal,
                                       glm::cross(za, zb));
      for (double radius : {10.0, 1000.0}) {
        const Image8 ia = renderFrom(rig_[a], view, radius), ib = renderFrom(rig_[b], view, radius);
        double gap = 0.0, overlap = 0.0;
        int rows = 0;
        for (int y = 118; y < 138; ++y, ++rows)
          for (int x = 0; x < view.width; ++x) {
            const bool ca0 = ia.px(x, y)[3] > 0, cb0 = ib.px(x, y)[3] > 0;
            gap += !ca0 && !cb0;
            overlap += ca0 && cb0;
          }
        // Back to the photographs' pixels (the view has a quarter of their focal length).
        const double scale = ca.focal.x / viewFocal / rows;
        std::printf("seam %s | %s, axes %.0f deg apart, radius %5.0f: gap %.1f px, overlap %.1f px\n",
                    ca.id.c_str(), cb.id.c_str(), glm::degrees(std::acos(glm::dot(za, zb))), radius, gap * scale,
                    overlap * scale);
        ++pairs;
      }
    }
  EXPECT_GT(pairs, 0);
}

}  // namespace
}  // namespace hv::render
