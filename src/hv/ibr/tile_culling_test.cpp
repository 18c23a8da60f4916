#include "hv/ibr/tile_culling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace hv::ibr {
namespace {

Camera looking(glm::dvec3 c, double yawDeg, int w, int h, double f) {
  Camera cam;
  cam.id = "c";
  cam.width = w;
  cam.height = h;
  cam.center = c;
  const double a = yawDeg * M_PI / 180.0;
  const glm::dvec3 z(std::cos(a), std::sin(a), 0.0), x = glm::normalize(glm::cross(z, glm::dvec3(0, 0, 1)));
  const glm::dvec3 y = glm::cross(z, x);
  cam.camFromWorld = glm::transpose(glm::dmat3(x, y, z));
  cam.focal = {f, f};
  cam.principal = {w / 2.0, h / 2.0};
  return cam;
}

TEST(TileCulling, ListsEveryImageThatCoversAPointOfTheTile) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const glm::dvec3 origin(651000.0, 6862000.0, 40.0);
  const Camera view = looking(origin + glm::dvec3(0, -30, 2), 90.0, 96, 64, 80.0);
  TileGrid g;
  g.tileSize = 16;
  g.depthSize = {96, 64};
  g.rect = idealRectCoveringImage(view);
  g.rect.near = 0.5;
  g.rect.far = 100.0;
  // Photographs scattered around, looking in random directions; some distorted.
  std::vector<ImageParams> images;
  for (int i = 0; i < 40; ++i) {
    Camera c = looking(origin + glm::dvec3(40 * u(rng) - 20, 40 * u(rng) - 10, 1 + 10 * u(rng)), 360 * u(rng), 64,
                       48, 30 + 60 * u(rng));
    if (i % 3 == 0) {
      LensDistortion d;
      d.center = {32.0, 24.0};
      d.c3 = -2e-4;
      d.r2max = 40.0 * 40.0;
      c.distortion = d;
    }
    images.push_back(makeImageParams(c, origin, {}, 1.0, idealRectCoveringImage(c), {}));
  }
  std::vector<TileDepth> depth(size_t(g.tilesX()) * g.tilesY());
  for (auto& d : depth) {
    d.empty = u(rng) < 0.1;
    d.zMin = 2.0 + 30.0 * u(rng);
    d.zMax = d.zMin + 20.0 * u(rng);
  }
  const TileLists lists = buildTileLists(view, origin, g, depth, images);
  const glm::dmat3 dirFromPix = glm::transpose(view.camFromWorld) * view.camFromPix();
  int checked = 0, covering = 0;
  for (int ty = 0; ty < g.tilesY(); ++ty)
    for (int tx = 0; tx < g.tilesX(); ++tx) {
      const size_t t = size_t(ty) * g.tilesX() + tx;
      if (depth[t].empty) {
        EXPECT_TRUE(lists.lists[t].empty());
        continue;
      }
      // Random points of the tile's slab: any image whose distorted domain contains one must be listed.
      for (int s = 0; s < 200; ++s) {
        const glm::dvec2 texel((tx + u(rng)) * g.tileSize, (ty + u(rng)) * g.tileSize);
        if (texel.x > g.depthSize.x || texel.y > g.depthSize.y) continue;
        const glm::dvec2 px = g.rect.pxMin + texel / glm::dvec2(g.depthSize) * (g.rect.pxMax - g.rect.pxMin);
        const double z = depth[t].zMin + u(rng) * (depth[t].zMax - depth[t].zMin);
        const glm::dvec3 P = view.center + z * (dirFromPix * glm::dvec3(px, 1.0));
        for (size_t i = 0; i < images.size(); ++i) {
          ++checked;
          if (!images[i].camera.project(P).inImage) continue;
          ++covering;
          const auto& l = lists.lists[t];
          EXPECT_NE(std::find(l.begin(), l.end(), std::uint16_t(i)), l.end()) << "tile " << tx << "," << ty;
        }
      }
    }
  EXPECT_GT(covering, 100);  // the check was exercised
  EXPECT_GT(checked, 10000);
  EXPECT_LT(lists.meanCount(), double(images.size()));  // and the lists do cull
}

TEST(TileCulling, DecodesTheShaderEncodingConservatively) {
  TileGrid g;
  g.tileSize = 8;
  g.depthSize = {16, 8};  // 2 x 1 tiles
  g.rect.near = 1.0;
  g.rect.far = 101.0;
  // Tile 0: min 0x1234, max 0x5678; tile 1: empty (min > max).
  const std::vector<std::uint8_t> rgba = {0x12, 0x34, 0x56, 0x78, 0xff, 0xff, 0x00, 0x00};
  const auto d = decodeTileDepth(rgba, g);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_FALSE(d[0].empty);
  EXPECT_NEAR(d[0].zMin, 1.0 + 100.0 * 0x1234 / 65535.0, 1e-12);
  EXPECT_NEAR(d[0].zMax, 1.0 + 100.0 * 0x5678 / 65535.0, 1e-12);
  EXPECT_TRUE(d[1].empty);
}

}  // namespace
}  // namespace hv::ibr
