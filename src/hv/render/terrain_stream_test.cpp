#include "hv/render/terrain_stream.h"

#include "hv/render/frame.h"

#include "hv/camera/frustum.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv::render {
namespace {

// 257 x 257 samples of 2 m, rolling hills: 16-cell tiles, levels 0..4.
std::shared_ptr<TerrainQuadtree> makeTree() {
  Heightfield h;
  h.cols = h.rows = 257;
  h.originX = 1000.0, h.originY = 3000.0;
  h.cellX = 2.0, h.cellY = -2.0;
  h.z.resize(size_t(h.cols) * h.rows);
  for (int j = 0; j < h.rows; ++j)
    for (int i = 0; i < h.cols; ++i)
      h.z[size_t(j) * h.cols + i] = float(20.0 * std::sin(0.05 * i) * std::cos(0.04 * j) + 3.0 * std::sin(0.7 * i + j));
  return std::make_shared<TerrainQuadtree>(std::make_shared<HeightfieldTerrainSource>(h), TerrainTileOptions{16});
}

const glm::dvec3 kOrigin(1200.0, 2800.0, 0.0);
// High above the middle, looking down: what a load-time cut for an aerial photograph sees.
Camera aerial() {
  return lookAtCamera("aerial", {1256.0, 2744.0, 3000.0}, {1256.0, 2744.0, 0.0}, 800, 600, 800.0, {0, 1, 0});
}
// Low over the north-west corner, looking along the ground.
Camera lowNorthWest() { return lookAtCamera("nw", {1010.0, 2990.0, 40.0}, {1100.0, 2900.0, 0.0}, 800, 600, 800.0); }
Camera lowSouthEast() { return lookAtCamera("se", {1502.0, 2498.0, 40.0}, {1400.0, 2600.0, 0.0}, 800, 600, 800.0); }

// Frames until the cut stops waiting (tiles read on this thread, a few per frame).
TerrainCut converge(TerrainStream& s, const Camera& cam, double tol, int* frames = nullptr) {
  for (int f = 0; f < 1000; ++f) {
    s.beginFrame();
    s.poll(std::chrono::microseconds(0));
    const TerrainCut cut = s.select(cam, tol, 0.0);
    s.endFrame();
    EXPECT_LE(s.residentBytes(), s.memoryBudget());
    if (cut.missing == 0) {
      if (frames) *frames = f + 1;
      return cut;
    }
  }
  ADD_FAILURE() << "no convergence";
  return {};
}

int finestLevelNear(const TerrainQuadtree& tree, const std::vector<TerrainNodeId>& nodes, glm::dvec2 p) {
  int finest = -1;
  for (TerrainNodeId id : nodes) {
    const TerrainTile t = tree.readTile(id);
    if (p.x >= t.bounds.lo.x && p.x <= t.bounds.hi.x && p.y >= t.bounds.lo.y && p.y <= t.bounds.hi.y)
      finest = std::max(finest, t.level);
  }
  return finest;
}

TEST(TerrainStream, AFrameWithMissingTilesCompletesAndImproves) {
  auto tree = makeTree();
  TerrainStream s(*tree, kOrigin, 0, std::size_t(64) << 20);
  s.beginFrame();
  TerrainCut cut = s.select(lowNorthWest(), 2.0, 0.0);
  EXPECT_TRUE(cut.nodes.empty());  // nothing resident yet: nothing to draw, the frame goes on
  EXPECT_EQ(cut.missing, 1);
  s.endFrame();
  // One tile a frame (no threads, no time budget): the root first, then the cut refines.
  s.beginFrame();
  const auto arrived = s.poll();
  ASSERT_EQ(arrived.size(), 1u);
  EXPECT_EQ(arrived[0].id, TerrainQuadtree::root());
  EXPECT_FALSE(arrived[0].indices.empty());
  EXPECT_EQ(arrived[0].vertices.size() % GeometryBuffers::kStride, 0u);
  cut = s.select(lowNorthWest(), 2.0, 0.0);
  EXPECT_EQ(cut.nodes, std::vector<TerrainNodeId>{TerrainQuadtree::root()});
  EXPECT_GT(cut.missing, 0);
  s.endFrame();
  int frames = 0;
  const TerrainCut done = converge(s, lowNorthWest(), 2.0, &frames);
  EXPECT_GT(frames, 3);
  EXPECT_GT(done.nodes.size(), 4u);
  EXPECT_EQ(s.pendingTiles(), 0u);
}

TEST(TerrainStream, ConvergedCutIsTheQuadtreeSelection) {
  // Whatever order the tiles arrived in, the cut is what TerrainQuadtree::select makes with every
  // tile at hand (an independent traversal reading tiles synchronously).
  auto tree = makeTree();
  for (const Camera& cam : {lowNorthWest(), aerial()}) {
    TerrainStream s(*tree, kOrigin, 0, std::size_t(64) << 20);
    EXPECT_EQ(converge(s, cam, 1.5).nodes, tree->select(cam, 1.5)) << cam.id;
  }
}

TEST(TerrainStream, AViewNearTheGroundIsFinerThereThanTheLoadTimeCut) {
  auto tree = makeTree();
  // The load-time cut: the photographs' cameras (here one aerial view) within a triangle budget.
  const TerrainSelection loadTime = tree->select(std::vector<Camera>{aerial()}, 8.0, 100000);
  TerrainStream s(*tree, kOrigin, 0, std::size_t(64) << 20);
  const TerrainCut view = converge(s, lowNorthWest(), 8.0);
  const glm::dvec2 underView(1020.0, 2980.0);
  const int loadLevel = finestLevelNear(*tree, loadTime.nodes, underView);
  const int viewLevel = finestLevelNear(*tree, view.nodes, underView);
  EXPECT_GE(loadLevel, 0);
  EXPECT_GT(viewLevel, loadLevel);
  EXPECT_EQ(viewLevel, tree->maxLevel());
  // Far from the view (the opposite corner) it is coarser than under it.
  EXPECT_LT(finestLevelNear(*tree, view.nodes, {1500.0, 2500.0}), viewLevel);
}

TEST(TerrainStream, RequestsGoInViewAndNearestFirst) {
  auto tree = makeTree();
  TerrainStream s(*tree, kOrigin, 0, std::size_t(64) << 20);
  converge(s, aerial(), 1e9);  // the root alone
  s.beginFrame();
  s.select(lowNorthWest(), 2.0, 0.0);  // asks for the root's four children
  s.endFrame();
  ASSERT_EQ(s.pendingTiles(), 4u);
  // The north-west quarter (tx 0 west, ty 0 north: the grid's rows go south) is the nearest.
  auto first = s.poll();
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0].id, TerrainQuadtree::makeId(1, 0, 0));
  // A camera over the south-east corner asks again at a better priority: its quarter comes next.
  s.beginFrame();
  s.select(lowSouthEast(), 2.0, -1.0);
  s.endFrame();
  auto next = s.poll();
  ASSERT_EQ(next.size(), 1u);
  EXPECT_EQ(next[0].id, TerrainQuadtree::makeId(1, 1, 1));
  // Out of the view's clip volume goes after everything in it, however near. North of the raster
  // looking west: the north-east quarter is the nearest and out of view, the north-west one in it.
  const Camera west = lookAtCamera("west", {1300.0, 3050.0, 30.0}, {1000.0, 3050.0, 0.0}, 800, 600, 800.0);
  hv::PinholeFrustum fr = hv::idealRectCoveringImage(west, 0.0);
  hv::setDepthRange(fr, west, tree->readTile(TerrainQuadtree::root()).bounds);
  const glm::dmat4 clip = hv::clipFromRender(west, fr, kOrigin);
  for (const bool withClip : {false, true}) {
    TerrainStream v(*tree, kOrigin, 0, std::size_t(64) << 20);
    converge(v, aerial(), 1e9);
    v.beginFrame();
    v.select(west, 0.01, 0.0, withClip ? &clip : nullptr);
    v.endFrame();
    const auto got = v.poll();
    ASSERT_EQ(got.size(), 1u);
    EXPECT_EQ(got[0].id, TerrainQuadtree::makeId(1, withClip ? 0 : 1, 0)) << withClip;
  }
}

TEST(TerrainStream, LruEvictionKeepsTheBudgetAndConvergesToTheSameCut) {
  auto tree = makeTree();
  // A budget that holds one low view's cut but not two (8 px: each refines its own corner).
  std::size_t need = 0;
  {
    TerrainStream probe(*tree, kOrigin, 0, std::size_t(64) << 20);
    converge(probe, lowNorthWest(), 8.0);
    need = probe.frameBytes();
    EXPECT_GE(need, probe.residentBytes());
  }
  TerrainStream s(*tree, kOrigin, 0, need + need / 5);
  const TerrainCut first = converge(s, lowNorthWest(), 8.0);
  EXPECT_EQ(first.nodes, tree->select(lowNorthWest(), 8.0));
  const TerrainCut other = converge(s, lowSouthEast(), 8.0);
  EXPECT_GT(s.evictions(), 0u);
  EXPECT_LE(s.residentBytes(), s.memoryBudget());
  EXPECT_LE(s.peakBytes(), s.memoryBudget() + need);  // arrivals may overshoot until the frame ends
  const TerrainCut back = converge(s, lowNorthWest(), 8.0);
  EXPECT_EQ(back.nodes, first.nodes);
  EXPECT_LE(s.residentBytes(), s.memoryBudget());
}

TEST(TerrainStream, ABudgetTooSmallLeavesTheCutCoarserNeverOver) {
  auto tree = makeTree();
  const std::size_t budget = 6 * (TerrainStream(*tree, kOrigin, 0, 1).tileBytesBound(TerrainQuadtree::root()));
  TerrainStream s(*tree, kOrigin, 0, budget);
  const TerrainCut cut = converge(s, lowNorthWest(), 2.0);
  EXPECT_TRUE(cut.budgetLimited);
  EXPECT_LE(cut.nodes.size(), 4u);
  EXPECT_LE(s.residentBytes(), budget);
}

TEST(TerrainStream, WorkerThreadsGiveTheSameCut) {
  auto tree = makeTree();
  TerrainStream s(*tree, kOrigin, 2, std::size_t(64) << 20);
  EXPECT_EQ(s.workerThreads(), 2);
  TerrainCut cut;
  for (int f = 0; f < 100; ++f) {
    s.beginFrame();
    s.waitAll([](TerrainTileMesh&&) {});
    cut = s.select(lowNorthWest(), 2.0, 0.0);
    s.endFrame();
    if (cut.missing == 0) break;
  }
  EXPECT_EQ(cut.missing, 0);
  EXPECT_EQ(cut.nodes, tree->select(lowNorthWest(), 2.0));
}

TEST(TerrainStream, RejectsBadArguments) {
  auto tree = makeTree();
  EXPECT_THROW(TerrainStream(*tree, kOrigin, -1, 1), std::invalid_argument);
  EXPECT_THROW(TerrainStream(*tree, kOrigin, 0, 0), std::invalid_argument);
}

}  // namespace
}  // namespace hv::render
