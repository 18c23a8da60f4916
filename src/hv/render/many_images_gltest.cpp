// Many images in one pass: a wall covered by 256 small photographs, each seeing only
// its own patch, rendered with K = 256, with and without per-tile culling.
#include "hv/eval/metrics.h"
#include "hv/render/renderer.h"
#include "hv/render/testing/gl_test_support.h"
#include "hv/image/native/png_write.h"

#include <gtest/gtest.h>

#include <iostream>

namespace hv::render {
namespace {

constexpr int kPatches = 16;  // 16 x 16 patches of 1 m on a 16 m wall

// A distinct colour per photograph.
glm::ivec3 patchColour(int i) { return {40 + 13 * (i % 16), 40 + 13 * (i / 16), 200 - 9 * (i % 7)}; }

TEST(ManyImagesGlTest, TwoHundredFiftySixPhotographsInOnePass) {
  testing::glContext();
  gpu::clearGlErrors();
  const glm::dvec3 o = testing::kStreetOrigin;
  Scene scene;
  scene.origin = o;
  // The wall: the plane y = 10 (facing -y), x in [0, 16], z in [0, 16] above the origin.
  scene.buildings.positions = {o + glm::dvec3(0, 10, 0), o + glm::dvec3(16, 10, 0), o + glm::dvec3(16, 10, 16),
                               o + glm::dvec3(0, 10, 16)};
  scene.buildings.triangles = {{0, 2, 1}, {0, 3, 2}};
  const std::string dir = testing::makeTempDir("many-images");
  for (int i = 0; i < kPatches * kPatches; ++i) {
    const glm::dvec3 patchCentre = o + glm::dvec3(i % kPatches + 0.5, 10, i / kPatches + 0.5);
    // 1 m in front of its patch, looking at it; 8 px covering 0.8 m: sees its own patch only.
    Camera c = testing::lookAt("p" + std::to_string(i), patchCentre - glm::dvec3(0, 1, 0), patchCentre, 8, 8, 10.0);
    const glm::ivec3 col = patchColour(i);
    Photo p;
    p.camera = c;
    p.imagePath = dir + "/" + c.id + ".png";
    writePng(p.imagePath, testing::solidImage(8, 8, std::uint8_t(col.r), std::uint8_t(col.g), std::uint8_t(col.b)));
    scene.photos.push_back(p);
  }
  RenderSettings s;
  s.blend.k = 256;
  s.blend.sigma = 100.0;
  s.depthSize = 32;
  s.maxSlices = 256;
  Diagnostics diag;
  Renderer renderer(scene, s, diag);
  ASSERT_GE(renderer.sliceCount(), 256);
  // The view sees the whole wall from 20 m: 20 px per patch.
  const Camera view = testing::lookAt("v", o + glm::dvec3(8, -10, 8), o + glm::dvec3(8, 10, 8), 320, 320, 400.0);
  const RenderOutput culled = renderer.render(view, true);
  ASSERT_EQ(renderer.lastPlan().images.size(), 256u);  // one pass, every photograph
  ASSERT_EQ(renderer.lastImageParams().size(), 256u);
  const double meanList = renderer.stats().meanTileList;
  const int maxList = renderer.stats().maxTileList;

  // Each patch shows its own photograph, exactly (no other image covers it).
  int patchesOk = 0;
  for (int i = 0; i < kPatches * kPatches; ++i) {
    const glm::dvec3 centre = o + glm::dvec3(i % kPatches + 0.5, 10, i / kPatches + 0.5);
    const glm::dvec2 px = view.project(centre).pxIdeal;
    const std::uint8_t* g = culled.rgba.px(int(px.x), int(px.y));
    const glm::ivec3 col = patchColour(i);
    const bool ok = g[3] == 255 && g[0] == col.r && g[1] == col.g && g[2] == col.b;
    EXPECT_TRUE(ok) << "patch " << i << " shows " << int(g[0]) << "," << int(g[1]) << "," << int(g[2]);
    patchesOk += ok;
    EXPECT_EQ(culled.counts.at(int(px.x), int(px.y), 0), 1);
  }
  EXPECT_EQ(patchesOk, 256);

  // Loop lengths: each fragment visits only its tile's list, far fewer than K = 256.
  int maxLoop = 0;
  double sumLoop = 0.0;
  int covered = 0;
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      if (culled.rgba.at(x, y, 3) == 0) continue;
      maxLoop = std::max<int>(maxLoop, culled.loopLengths.at(x, y, 0));
      sumLoop += culled.loopLengths.at(x, y, 0);
      ++covered;
    }
  std::cout << "256 images, culled: mean loop length " << sumLoop / covered << ", max " << maxLoop
            << " (tile lists: mean " << meanList << ", max " << maxList << ")\n";
  EXPECT_LE(maxLoop, 9);  // a 16 px tile spans at most 2 x 2 patches of 20 px, plus conservative margins
  EXPECT_LE(maxLoop, maxList);

  // Without culling: every fragment loops over all 256, and the picture is the same.
  renderer.settings().tileCulling = false;
  const RenderOutput full = renderer.render(view, true);
  EXPECT_EQ(full.loopLengths.at(160, 160, 0), 256);
  std::vector<std::uint8_t> all(size_t(view.width) * view.height, 1);
  const double psnr = eval::compareImages(culled.rgba, full.rgba, all).psnr;
  std::cout << "culled vs unculled: PSNR " << psnr << " dB\n";
  EXPECT_GE(psnr, 45.0);
  EXPECT_TRUE(diag.ok());
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

}  // namespace
}  // namespace hv::render

namespace hv::render {
namespace {

TEST(ManyImagesGlTest, FourThousandPhotographsThroughSixtyFourSlots) {
  testing::glContext();
  gpu::clearGlErrors();
  constexpr int kSide = 64;  // 64 x 64 patches of 1 m: 4096 photographs
  const glm::dvec3 o = testing::kStreetOrigin;
  Scene scene;
  scene.origin = o;
  scene.buildings.positions = {o + glm::dvec3(0, 10, 0), o + glm::dvec3(kSide, 10, 0),
                               o + glm::dvec3(kSide, 10, kSide), o + glm::dvec3(0, 10, kSide)};
  scene.buildings.triangles = {{0, 2, 1}, {0, 3, 2}};
  const std::string dir = testing::makeTempDir("residency");
  for (int i = 0; i < kSide * kSide; ++i) {
    const glm::dvec3 c = o + glm::dvec3(i % kSide + 0.5, 10, i / kSide + 0.5);
    Photo p;
    p.camera = testing::lookAt("p" + std::to_string(i), c - glm::dvec3(0, 1, 0), c, 4, 4, 5.0);
    p.imagePath = dir + "/" + p.camera.id + ".png";
    const glm::ivec3 col(i % 256, (i / 256) * 16, 255 - i % 200);
    writePng(p.imagePath, testing::solidImage(4, 4, std::uint8_t(col.r), std::uint8_t(col.g), std::uint8_t(col.b)));
    scene.photos.push_back(p);
  }
  RenderSettings s;
  s.blend.k = 64;
  s.blend.sigma = 100.0;
  s.depthSize = 16;
  s.maxSlices = 64;                         // the slot budget
  s.decodeMemoryBytes = 64 * 1024;          // the decode cap: a few tiny photographs at a time
  Diagnostics diag;
  Renderer renderer(scene, s, diag);
  ASSERT_EQ(renderer.sliceCount(), 64);
  // A view of an 8 x 8 block of patches needs exactly those 64 photographs.
  auto blockView = [&](int bx, int by) {
    const glm::dvec3 centre = o + glm::dvec3(bx * 8 + 4, 10, by * 8 + 4);
    // Sees 7.9 m of the 8 m block at 8 m: no neighbouring photograph's frustum (0.8 m wide, centred
    // 0.5 m beyond the block) reaches the view, so the 64 candidates are exactly the block's.
    return testing::lookAt("v", centre - glm::dvec3(0, 8, 0), centre, 96, 96, 96.0 * 8.0 / 7.9);
  };
  auto checkBlock = [&](const RenderOutput& out, const Camera& view, int bx, int by) {
    int ok = 0;
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i) {
        const int idx = (by * 8 + j) * kSide + bx * 8 + i;
        const glm::dvec2 px = view.project(o + glm::dvec3(bx * 8 + i + 0.5, 10, by * 8 + j + 0.5)).pxIdeal;
        const std::uint8_t* g = out.rgba.px(int(px.x), int(px.y));
        ok += g[3] == 255 && g[0] == idx % 256 && g[1] == (idx / 256) * 16 && g[2] == 255 - idx % 200;
      }
    return ok;
  };
  const Camera first = blockView(1, 1);
  const RenderOutput a = renderer.render(first);
  EXPECT_EQ(checkBlock(a, first, 1, 1), 64) << "every patch of the block textured by its own photograph";
  const int loadedFirst = renderer.stats().imagesLoaded;
  EXPECT_LE(loadedFirst, 64);
  // Elsewhere: the slots are reused (the first block's photographs are evicted)...
  const Camera second = blockView(6, 5);
  EXPECT_EQ(checkBlock(renderer.render(second), second, 6, 5), 64);
  // ...and they come back when the view returns, giving the same picture.
  const RenderOutput again = renderer.render(first);
  EXPECT_EQ(again.rgba.data, a.rgba.data);
  EXPECT_GT(renderer.stats().imagesLoaded, loadedFirst + 64);
  // Memory: the slice arrays are sized from the slot budget, the decodes stay under their cap.
  // Per slot: the 4 x 4 slice's mip chain (16 + 4 + 1 texels) and a 16 x 16 depth map.
  EXPECT_EQ(renderer.stats().sliceBytes, size_t(64) * ((16 + 4 + 1) * 4 + 16 * 16 * 4));
  EXPECT_LE(renderer.stats().decodePeakBytes, s.decodeMemoryBytes);
  EXPECT_GT(renderer.stats().decodePeakBytes, 0u);
  EXPECT_TRUE(diag.ok());
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

}  // namespace
}  // namespace hv::render
