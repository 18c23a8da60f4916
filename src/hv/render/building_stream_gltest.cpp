// Streamed buildings in the GL renderer (render/building_stream.h, docs/design.md "Building
// streaming"): the demo city's buildings cut into tiles that the renderer reads per view must give
// the picture of the same buildings drawn whole, in batch frames and once progressive frames have
// converged, with their validity dates honoured.
#include "hv/eval/metrics.h"
#include "hv/render/renderer.h"
#include "hv/render/testing/gl_test_support.h"
#include "hv/scene/building_tiles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <map>

namespace hv::render {
namespace {

using testing::demoCity;

double psnr(const Image8& a, const Image8& b) {
  return eval::compareImages(a, b, std::vector<std::uint8_t>(std::size_t(a.width) * a.height, 1)).psnr;
}

class BuildingStreamGlTest : public testing::GlTest {};

// The scene's buildings as an n x n grid of tiles over their ground extent, each building owned by
// the cell of its first vertex (as the loader's tiles own theirs), read from memory on demand.
// Boxes are the cells widened by one cell, with the buildings' heights widened by `zMargin`.
std::shared_ptr<BuildingTileSet> tiledBuildings(const Scene& scene, int n, double zMargin,
                                                std::shared_ptr<std::atomic<int>> reads) {
  const Mesh& m = scene.buildings;
  const Aabb all = m.bounds();
  const glm::dvec2 cell = (glm::dvec2(all.hi) - glm::dvec2(all.lo)) / double(n);
  // Per building (triangle tag), its triangles; per tile, its buildings.
  std::map<std::uint32_t, std::vector<std::size_t>> trianglesOf;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) trianglesOf[m.triangleTags[t]].push_back(t);
  auto tiles = std::make_shared<std::vector<std::vector<std::uint32_t>>>(std::size_t(n * n));
  for (const auto& [tag, tris] : trianglesOf) {
    const glm::dvec3 p = m.positions[m.triangles[tris.front()][0]];
    const int i = std::clamp(int((p.x - all.lo.x) / cell.x), 0, n - 1);
    const int j = std::clamp(int((p.y - all.lo.y) / cell.y), 0, n - 1);
    (*tiles)[std::size_t(j * n + i)].push_back(tag);
  }
  auto set = std::make_shared<BuildingTileSet>();
  for (int t = 0; t < n * n; ++t) {
    Aabb b;
    b.lo = {all.lo.x + (t % n - 1) * cell.x, all.lo.y + (t / n - 1) * cell.y, all.lo.z - zMargin};
    b.hi = {all.lo.x + (t % n + 2) * cell.x, all.lo.y + (t / n + 2) * cell.y, all.hi.z + zMargin};
    set->boxes.push_back(b);
  }
  set->read = [&scene, tiles, trianglesOf, reads](std::uint32_t t) {
    if (reads) ++*reads;
    BuildingTileData d;
    for (std::uint32_t tag : (*tiles)[t]) {
      Mesh b;
      std::map<std::uint32_t, std::uint32_t> vertex;
      for (std::size_t tri : trianglesOf.at(tag)) {
        glm::uvec3 out;
        for (int k = 0; k < 3; ++k) {
          const std::uint32_t v = scene.buildings.triangles[tri][k];
          auto [it, added] = vertex.emplace(v, std::uint32_t(b.positions.size()));
          if (added) b.positions.push_back(scene.buildings.positions[v]);
          out[k] = it->second;
        }
        b.triangles.push_back(out);
      }
      b.triangleTags.assign(b.triangles.size(), std::uint32_t(d.validity.size()));
      d.mesh.append(b);
      d.validity.push_back(tag < scene.buildingValidity.size() ? scene.buildingValidity[tag] : DateInterval{});
    }
    return d;
  };
  return set;
}

TEST_F(BuildingStreamGlTest, StreamedBuildingsGiveTheWholeLoadsPicture) {
  const Scene& whole = demoCity().scene;
  ASSERT_GT(whole.buildingValidity.size(), 20u);
  Scene streamed = whole;
  auto reads = std::make_shared<std::atomic<int>>(0);
  streamed.buildingTiles = tiledBuildings(whole, 4, 50.0, reads);
  // Dated buildings: a photograph of a date before one existed must not see it (validity texels
  // come with the tiles; the demo's own buildings are all open-ended).
  ASSERT_FALSE(whole.photos.empty());
  Scene wholeDated = whole;
  for (std::size_t b = 0; b < wholeDated.buildingValidity.size(); b += 3)
    wholeDated.buildingValidity[b].first = parseDate("2100-01-01")->first;
  Scene streamedDated = wholeDated;
  streamedDated.buildingTiles = tiledBuildings(wholeDated, 4, 50.0, nullptr);

  RenderSettings s;
  s.blend.k = 6;
  s.depthSize = 512;
  bool datesChangeThePicture = false;  // so that the dated comparison is about them
  for (const Photo& v : {demoCity().views[0], demoCity().views[2]}) {
    Diagnostics diag;
    Renderer a(whole, s, diag), b(streamed, s, diag);
    const RenderOutput ra = a.render(v.camera), rb = b.render(v.camera);
    EXPECT_TRUE(b.stats().streamingBuildings);
    EXPECT_GT(b.stats().buildingTilesResident, 1);
    EXPECT_EQ(b.stats().buildingViewMissing, 0);
    EXPECT_EQ(b.stats().buildingTilesPending, 0);
    EXPECT_TRUE(b.converged());
    const double streamedPsnr = psnr(rb.rgba, ra.rgba);
    std::cout << v.camera.id << ": streamed vs whole " << streamedPsnr << " dB, " << b.stats().buildingTilesResident
              << " tiles resident, " << b.stats().buildingViewTiles << " in the view's cut\n";
    EXPECT_GE(streamedPsnr, 50.0) << v.camera.id;

    Renderer ad(wholeDated, s, diag), bd(streamedDated, s, diag);
    const RenderOutput rad = ad.render(v.camera), rbd = bd.render(v.camera);
    const double dated = psnr(rbd.rgba, rad.rgba);
    EXPECT_GE(dated, 50.0) << v.camera.id;
    datesChangeThePicture = datesChangeThePicture || psnr(rad.rgba, ra.rgba) < 45.0;
    EXPECT_TRUE(diag.ok());
  }
  EXPECT_TRUE(datesChangeThePicture);
  EXPECT_GT(reads->load(), 0);
}

TEST_F(BuildingStreamGlTest, ProgressiveFramesWithStreamedBuildingsConvergeToTheBatchFrame) {
  const Scene& whole = demoCity().scene;
  Scene streamed = whole;
  streamed.buildingTiles = tiledBuildings(whole, 4, 50.0, nullptr);
  const Camera& view = demoCity().views[1].camera;
  RenderSettings s;
  s.blend.k = 6;
  s.depthSize = 512;
  s.geometryThreads = 1;
  Diagnostics diag;
  Renderer batch(streamed, s, diag);
  const RenderOutput expected = batch.render(view);

  Renderer progressive(streamed, s, diag);
  RenderOutput out = progressive.render(view, false, FrameMode::Progressive);
  // The first frame completes whatever has arrived.
  EXPECT_EQ(out.rgba.width, view.width);
  int frames = 1;
  while (!progressive.converged() && frames < 200) {
    out = progressive.render(view, false, FrameMode::Progressive);
    ++frames;
  }
  ASSERT_TRUE(progressive.converged()) << frames << " frames";
  EXPECT_EQ(out.rgba.data, expected.rgba.data);
  EXPECT_TRUE(diag.ok());
}

}  // namespace
}  // namespace hv::render
