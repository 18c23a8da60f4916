// GL test of the terrain streamed per view (render/terrain_stream.h) on a small DTM: a frame drawn
// while tiles are missing completes, the progressive frames converge to the batch frame bit for
// bit (tiles read on the render thread or by workers), depth maps are redrawn only when their cut
// changes, and under a small memory budget the least recently used tiles are evicted, the budget
// holds and a view seen again converges to the same picture.
#include "hv/render/renderer.h"

#include "hv/image/native/png_write.h"
#include "hv/render/testing/gl_test_support.h"
#include "hv/scene/terrain_quadtree.h"

#include <gtest/gtest.h>

#include <chrono>
#include <set>
#include <thread>

namespace hv::render {
namespace {

const glm::dvec3 kOrigin(1256.0, 2744.0, 0.0);

// 257 x 257 samples of 2 m (16-cell tiles, levels 0..4), rolling hills, photographed from four
// oblique cameras; `terrain` is the load-time cut for them, as the scene loader makes it.
Scene hillScene() {
  Heightfield h;
  h.cols = h.rows = 257;
  h.originX = 1000.0, h.originY = 3000.0;
  h.cellX = 2.0, h.cellY = -2.0;
  h.z.resize(size_t(h.cols) * h.rows);
  for (int j = 0; j < h.rows; ++j)
    for (int i = 0; i < h.cols; ++i)
      h.z[size_t(j) * h.cols + i] = float(20.0 * std::sin(0.05 * i) * std::cos(0.04 * j) + 0.3 * std::sin(0.7 * i + j));
  Scene s;
  s.origin = kOrigin;
  s.terrainTiles =
      std::make_shared<TerrainQuadtree>(std::make_shared<HeightfieldTerrainSource>(h), TerrainTileOptions{16});
  const std::string dir = testing::makeTempDir("terrain-stream");
  const glm::dvec3 c = kOrigin;
  const glm::dvec3 centres[4] = {c + glm::dvec3(-150, -150, 90), c + glm::dvec3(150, -150, 90),
                                 c + glm::dvec3(150, 150, 90), c + glm::dvec3(-150, 150, 90)};
  std::vector<Camera> cams;
  for (int i = 0; i < 4; ++i) {
    Photo p;
    p.camera = testing::lookAt("p" + std::to_string(i), centres[i], c + 0.3 * (centres[i] - c) - glm::dvec3(0, 0, 27),
                               160, 120, 140.0);
    p.imagePath = dir + "/" + p.camera.id + ".png";
    writePng(p.imagePath, testing::patternImage(160, 120, i + 1));
    cams.push_back(p.camera);
    s.photos.push_back(p);
  }
  s.terrain = s.terrainTiles->mesh(s.terrainTiles->select(cams, 2.0, 2'000'000).nodes);
  return s;
}

Camera viewA() {
  return testing::lookAt("a", kOrigin + glm::dvec3(-200, -200, 30), kOrigin + glm::dvec3(-100, -120, 0), 200, 150,
                         180.0);
}
Camera viewB() {
  return testing::lookAt("b", kOrigin + glm::dvec3(200, 200, 30), kOrigin + glm::dvec3(100, 120, 0), 200, 150, 180.0);
}

class TerrainStreamGlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    testing::glContext();
    gpu::clearGlErrors();
  }
  void TearDown() override { EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR)); }

  static RenderSettings settings(int geometryThreads) {
    RenderSettings s;
    s.blend.k = 3;
    s.depthSize = 256;
    s.decodeThreads = 0;
    s.geometryThreads = geometryThreads;
    return s;
  }

  // Progressive frames until the renderer says converged; the last frame's picture.
  static Image8 converge(Renderer& r, const Camera& view, int threads, int* frames) {
    RenderOutput out;
    for (int f = 0; f < 2000; ++f) {
      out = r.render(view, false, FrameMode::Progressive);
      EXPECT_EQ(out.rgba.width, view.width);
      EXPECT_EQ(out.rgba.height, view.height);
      if (r.converged()) {
        *frames = f + 1;
        return out.rgba;
      }
      if (threads > 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ADD_FAILURE() << "no convergence";
    return out.rgba;
  }
};

TEST_F(TerrainStreamGlTest, ProgressiveFramesCompleteAndConvergeToTheBatchFrame) {
  const Scene scene = hillScene();
  Diagnostics diag;
  Renderer batch(scene, settings(0), diag);
  const RenderOutput truth = batch.render(viewA());
  ASSERT_TRUE(batch.converged());
  ASSERT_TRUE(batch.stats().streamingTerrain);
  EXPECT_EQ(batch.stats().terrainViewMissing, 0);
  EXPECT_GT(batch.stats().terrainViewTiles, 4);
  // The view's ground is textured by the photographs' patterns: many colours.
  std::set<std::uint32_t> colours;
  for (size_t i = 0; i + 2 < truth.rgba.data.size(); i += 4)
    colours.insert(std::uint32_t(truth.rgba.data[i]) << 16 | std::uint32_t(truth.rgba.data[i + 1]) << 8 |
                   truth.rgba.data[i + 2]);
  EXPECT_GT(colours.size(), 200u);

  for (const int threads : {0, 2}) {
    Renderer progressive(scene, settings(threads), diag);
    // The first frame has nothing of the terrain yet and completes anyway.
    const RenderOutput first = progressive.render(viewA(), false, FrameMode::Progressive);
    EXPECT_EQ(first.rgba.data.size(), truth.rgba.data.size());
    EXPECT_FALSE(progressive.converged());
    EXPECT_GT(progressive.stats().terrainTilesPending + progressive.stats().terrainViewMissing, 0);
    int frames = 0;
    const Image8 last = converge(progressive, viewA(), threads, &frames);
    EXPECT_GT(frames, 2) << threads;
    EXPECT_TRUE(last.data == truth.rgba.data) << "the converged frame differs from the batch one, threads " << threads;
    // Nothing arrives any more: no depth map is redrawn.
    const int drawn = progressive.stats().depthMapsRendered;
    progressive.render(viewA(), false, FrameMode::Progressive);
    EXPECT_EQ(progressive.stats().depthMapsRendered, drawn);
    EXPECT_TRUE(progressive.converged());
  }
  EXPECT_TRUE(diag.ok());
}

TEST_F(TerrainStreamGlTest, LruUnderASmallBudgetKeepsItAndConvergesToTheSamePicture) {
  const Scene scene = hillScene();
  Diagnostics diag;
  RenderSettings roomy = settings(0);
  Renderer probe(scene, roomy, diag);
  const RenderOutput truth = probe.render(viewA());
  // What view A's cuts and its photographs' reserve (bounds of their tiles' bytes).
  const std::size_t need = probe.stats().terrainFrameBytes;
  ASSERT_GT(need, 0u);
  ASSERT_GE(need, probe.stats().terrainBytes);

  RenderSettings tight = roomy;
  tight.geometryMemoryBytes = need + need / 5;
  Renderer r(scene, tight, diag);
  EXPECT_TRUE(r.render(viewA()).rgba.data == truth.rgba.data);
  EXPECT_LE(r.stats().terrainBytes, tight.geometryMemoryBytes);
  r.render(viewB());
  EXPECT_LE(r.stats().terrainBytes, tight.geometryMemoryBytes);
  EXPECT_GT(r.stats().terrainEvictions, 0u);
  const RenderOutput again = r.render(viewA());
  EXPECT_LE(r.stats().terrainBytes, tight.geometryMemoryBytes);
  EXPECT_TRUE(again.rgba.data == truth.rgba.data) << "view A seen again differs";
  // Progressively as well.
  r.render(viewB());
  int frames = 0;
  EXPECT_TRUE(converge(r, viewA(), 0, &frames).data == truth.rgba.data);
  EXPECT_LE(r.stats().terrainBytes, tight.geometryMemoryBytes);
  EXPECT_TRUE(diag.ok());
}

}  // namespace
}  // namespace hv::render
