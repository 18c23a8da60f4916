// The per-configuration shade programs (render/gl/shade_config.h) against the one generic program,
// on llvmpipe: for each option alone and together, the same picture and the same per-pixel counts.
// Both are checked against the CPU reference by RendererGlTest; this pins the specialisation
// itself (a constant folded the wrong way, a list shifted off by one) pixel by pixel.
#include "hv/render/gl/shade_config.h"

#include "hv/ibr/frame_plan.h"
#include "hv/image/native/png_write.h"
#include "hv/render/renderer.h"
#include "hv/render/testing/gl_test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <string>

namespace hv::render {
namespace {

using testing::kStreetOrigin;

class ShadeConfigGlTest : public testing::PhotoGlTest {
 protected:
  void TearDown() override {
    gl::setShadeSpecialisation(true);
    PhotoGlTest::TearDown();
  }

  // Renders `view` with the generic program and with the frame's own, and compares the pictures
  // (at most 1/255 apart: the same arithmetic, reordered by the compiler) and the counts of
  // images blended (equal but where a weight sits within rounding of 0: at most 0.5 % of pixels).
  void compareSpecialised(const Scene& scene, const RenderSettings& settings, const Camera& view,
                          const std::string& what) {
    Diagnostics diag;
    Renderer renderer(scene, settings, diag);
    gl::setShadeSpecialisation(false);
    const RenderOutput generic = renderer.render(view, true);
    gl::setShadeSpecialisation(true);
    const RenderOutput own = renderer.render(view, true);
    ASSERT_TRUE(diag.ok()) << what;
    ASSERT_EQ(generic.rgba.data.size(), own.rgba.data.size()) << what;
    int worst = 0;
    size_t covered = 0;
    for (size_t i = 0; i < own.rgba.data.size(); ++i) {
      worst = std::max(worst, std::abs(int(own.rgba.data[i]) - int(generic.rgba.data[i])));
      if (i % 4 == 3 && own.rgba.data[i] > 0) ++covered;
    }
    EXPECT_LE(worst, 1) << what;
    EXPECT_GT(covered, own.rgba.data.size() / 4 / 4) << what << ": too little of the view is textured to compare";
    ASSERT_EQ(generic.counts.data.size(), own.counts.data.size()) << what;
    size_t differ = 0;
    for (size_t i = 0; i < own.counts.data.size(); ++i) differ += own.counts.data[i] != generic.counts.data[i];
    EXPECT_LE(differ, own.counts.data.size() / 200) << what;
  }
};

TEST_F(ShadeConfigGlTest, EveryOptionDrawsWhatTheGenericProgramDraws) {
  Scene scene = testing::streetScene();
  addStreetPhotos(scene, "abc", 110.0);
  Image8 mask(160, 120, 1, 255);
  for (int y = 40; y < 80; ++y)
    for (int x = 50; x < 110; ++x) mask.at(x, y, 0) = 0;
  addPhoto(scene, testing::streetPhotoCamera('d'), testing::patternImage(160, 120, 4), &mask);
  addStreetPhotos(scene, "e");
  const Camera view = testing::streetView();
  RenderSettings base;
  base.blend.sigma = 5.0;
  base.blend.k = 4;
  base.depthSize = 512;
  const std::pair<const char*, std::function<void(ibr::BlendSettings&)>> cases[] = {
      {"papers' blend", [](ibr::BlendSettings&) {}},
      {"geometry", [](ibr::BlendSettings& s) { s.weighting = ibr::Weighting::Geometry; }},
      {"geometry, K 2",
       [](ibr::BlendSettings& s) {
         s.weighting = ibr::Weighting::Geometry;
         s.k = 2;
         s.resolutionWeight = 2.0;
       }},
      {"geometry, geometry-k 1",
       [](ibr::BlendSettings& s) {
         s.weighting = ibr::Weighting::Geometry;
         s.geometryK = 1;
       }},
      {"geometry, feather, mipmaps",
       [](ibr::BlendSettings& s) {
         s.weighting = ibr::Weighting::Geometry;
         s.featherPx = 12.0;
         s.mipmaps = true;
         s.anisotropy = 1.0;
       }},
      {"distance, feather, mipmaps",
       [](ibr::BlendSettings& s) {
         s.featherPx = 12.0;
         s.mipmaps = true;
         s.anisotropy = 1.0;
       }},
      {"geometry, region",
       [](ibr::BlendSettings& s) {
         s.weighting = ibr::Weighting::Geometry;
         s.selection = ibr::Selection::Region;
       }},
      {"distance, region", [](ibr::BlendSettings& s) { s.selection = ibr::Selection::Region; }},
      {"geometry, transient filter",
       [](ibr::BlendSettings& s) {
         s.weighting = ibr::Weighting::Geometry;
         s.consensus = 0.25;
       }},
      {"geometry, nearest",
       [](ibr::BlendSettings& s) {
         s.weighting = ibr::Weighting::Geometry;
         s.method = ibr::BlendMethod::Nearest;
       }},
  };
  for (const auto& [name, apply] : cases) {
    RenderSettings s = base;
    apply(s.blend);
    compareSpecialised(scene, s, view, name);
  }
}

// The configuration names what the frame's photographs need and sizes the ranking to the longest
// candidate list (a multiple of 4, at most ibr::kMaxGeometryRank).
TEST(ShadeConfig, DefinesFollowTheFrame) {
  Frame f;
  f.blend.weighting = ibr::Weighting::Geometry;
  f.blend.k = 8;
  f.blend.geometryK = 3;
  f.packedParams.assign(size_t(ibr::kTexelsPerImage) * 4 * 2, 0.0f);
  f.packedParams[17] = -1.0f;                           // image 0: no lens model
  f.packedParams[ibr::kTexelsPerImage * 4 + 17] = 4.0f;  // image 1: a lens model, not a fish-eye
  auto has = [](const std::vector<std::string>& d, const std::string& x) {
    return std::find(d.begin(), d.end(), x) != d.end();
  };
  std::vector<std::string> d = gl::shadeConfigDefines(f, 9, 0.0f);
  EXPECT_TRUE(has(d, "HV_CONF_GEOMETRY=1"));
  EXPECT_TRUE(has(d, "HV_CONF_K=3"));
  EXPECT_TRUE(has(d, "HV_CONF_RANK=12"));
  EXPECT_TRUE(has(d, "HV_CONF_LENS=1"));
  EXPECT_TRUE(has(d, "HV_CONF_LAYERS=0"));
  EXPECT_TRUE(has(gl::shadeConfigDefines(f, 200, 0.0f), "HV_CONF_RANK=32"));
  f.packedParams[ibr::kTexelsPerImage * 4 + 42] = 1.0f;  // a fish-eye
  f.packedParams[35] = 2.0f;                             // image 0: a layered photograph's sub-image
  d = gl::shadeConfigDefines(f, 9, 0.0f);
  EXPECT_TRUE(has(d, "HV_CONF_LENS=2"));
  EXPECT_TRUE(has(d, "HV_CONF_LAYERS=1"));
  f.blend.method = ibr::BlendMethod::Nearest;  // nearest takes no weights
  EXPECT_TRUE(has(gl::shadeConfigDefines(f, 9, 0.0f), "HV_CONF_GEOMETRY=0"));
  f.blend.method = ibr::BlendMethod::Blend;
  f.blend.mipmaps = true;
  f.blend.anisotropy = 8.0;
  EXPECT_TRUE(has(gl::shadeConfigDefines(f, 9, 0.0f), "HV_CONF_MIPMAPS=1"));  // no extension
  EXPECT_TRUE(has(gl::shadeConfigDefines(f, 9, 16.0f), "HV_CONF_MIPMAPS=2"));
  EXPECT_NE(gl::shadeConfigKey(gl::shadeConfigDefines(f, 9, 0.0f)), gl::shadeConfigKey(gl::shadeConfigDefines(f, 13, 0.0f)));
}

}  // namespace
}  // namespace hv::render
