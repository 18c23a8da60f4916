#include "hv/render/building_stream.h"

#include "hv/camera/frustum.h"
#include "hv/render/frame.h"
#include "hv/render/geometry_tiles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>

namespace hv::render {
namespace {

// 8 x 8 tiles of 50 m from (1000, 3000); tile t holds (t % 3) + 1 boxes of 10 m, each 4 + t m tall,
// a building crossing into the next tile in x (the tile's first one, 70 m long, owned here) in every
// fifth tile. A tile's box before it is read is its cell widened by one cell (as the loader's).
constexpr int kTiles = 8;
constexpr double kCell = 50.0;
const glm::dvec3 kOrigin(1200.0, 3200.0, 0.0);

Mesh box(glm::dvec3 lo, glm::dvec3 hi, std::uint32_t tag) {
  Mesh m;
  for (int c = 0; c < 8; ++c) m.positions.push_back({c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z});
  const int f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                        {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& t : f) m.triangles.push_back(glm::uvec3(t[0], t[1], t[2]));
  m.triangleTags.assign(12, tag);
  return m;
}

BuildingTileData tileData(std::uint32_t t) {
  BuildingTileData d;
  const double x0 = 1000.0 + kCell * (t % kTiles), y0 = 3000.0 + kCell * (t / kTiles);
  const std::uint32_t n = t % 3 + 1;
  for (std::uint32_t b = 0; b < n; ++b) {
    const double x = x0 + 5.0 + 15.0 * b, y = y0 + 5.0;
    const double len = (b == 0 && t % 5 == 0 && t % kTiles != kTiles - 1) ? 70.0 : 10.0;
    d.mesh.append(box({x, y, 0.0}, {x + len, y + 10.0, 4.0 + t}, b));
    DateInterval v;
    if (t % 4 == 1) v.first = 700000 + t;
    d.validity.push_back(v);
  }
  return d;
}

std::shared_ptr<BuildingTileSet> makeSet(std::shared_ptr<std::atomic<int>> reads = nullptr) {
  auto set = std::make_shared<BuildingTileSet>();
  for (int t = 0; t < kTiles * kTiles; ++t) {
    Aabb b;
    const double x0 = 1000.0 + kCell * (t % kTiles), y0 = 3000.0 + kCell * (t / kTiles);
    b.lo = {x0 - kCell, y0 - kCell, -1000.0};
    b.hi = {x0 + 2 * kCell, y0 + 2 * kCell, 1000.0};
    set->boxes.push_back(b);
  }
  set->read = [reads](std::uint32_t t) {
    if (reads) ++*reads;
    return tileData(t);
  };
  return set;
}

struct View {
  Camera camera;
  glm::dmat4 clip;
};
View view(glm::dvec3 eye, glm::dvec3 target, double focal = 500.0) {
  View v{lookAtCamera("v", eye, target, 640, 480, focal), {}};
  Aabb scene;
  scene.lo = {1000.0, 3000.0, 0.0};
  scene.hi = {1400.0, 3400.0, 80.0};
  hv::PinholeFrustum fr = hv::idealRectCoveringImage(v.camera, 0.0);
  hv::setDepthRange(fr, v.camera, scene);
  v.clip = hv::clipFromRender(v.camera, fr, kOrigin);
  return v;
}
View aerial() { return view({1200.0, 3200.0, 3000.0}, {1200.0, 3200.0, 0.0}); }
// Street level along the southern and the northern rows, narrow (24 degrees across).
View lowWest() { return view({1005.0, 3025.0, 10.0}, {1400.0, 3025.0, 10.0}, 1500.0); }
View lowEast() { return view({1395.0, 3375.0, 10.0}, {1000.0, 3375.0, 10.0}, 1500.0); }

// Frames until the cut stops waiting.
BuildingCut converge(BuildingStream& s, const View& v, std::map<std::uint32_t, BuildingTileMesh>* got = nullptr,
                     int* frames = nullptr) {
  for (int f = 0; f < 10000; ++f) {
    s.beginFrame();
    for (BuildingTileMesh& m : s.poll()) {
      EXPECT_TRUE(m.error.empty()) << m.error;
      if (got) (*got)[m.tile] = std::move(m);
    }
    const BuildingCut cut = s.select(v.camera, v.clip, 0.0);
    for (std::uint32_t t : s.endFrame())
      if (got) got->erase(t);
    EXPECT_LE(s.residentBytes(), s.memoryBudget());
    if (cut.missing == 0 && s.pendingTiles() == 0) {
      if (frames) *frames = f + 1;
      return cut;
    }
  }
  ADD_FAILURE() << "no convergence";
  return {};
}

// The tiles whose buildings' box the clip volume may see, from the source itself.
std::vector<std::uint32_t> visibleTiles(const View& v) {
  std::vector<std::uint32_t> out;
  for (std::uint32_t t = 0; t < kTiles * kTiles; ++t) {
    const Aabb b = tileData(t).mesh.bounds();
    if (boxMayBeVisible(v.clip, glm::vec3(b.lo - kOrigin), glm::vec3(b.hi - kOrigin))) out.push_back(t);
  }
  return out;
}

TEST(BuildingStream, AFrameWithNothingLoadedCompletesAndRequestsNearestFirst) {
  auto reads = std::make_shared<std::atomic<int>>(0);
  BuildingStream s(makeSet(reads), kOrigin, 0, std::size_t(64) << 20);
  const View v = lowWest();
  s.beginFrame();
  const BuildingCut cut = s.select(v.camera, v.clip, 0.0);
  s.endFrame();
  EXPECT_TRUE(cut.tiles.empty());
  EXPECT_GT(cut.missing, 3);
  EXPECT_EQ(*reads, 0) << "select must not read";
  // With no worker, one poll reads the head of the queue only: the tile under the camera (tile 0's
  // box, like its neighbours', holds the camera: the nearest, the first in order).
  const auto first = s.poll();
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0].tile, 0u);
  EXPECT_EQ(*reads, 1);
}

TEST(BuildingStream, ConvergedCutIsTheTilesWhoseBuildingsTheViewMaySee) {
  for (const View& v : {aerial(), lowWest(), lowEast()}) {
    BuildingStream s(makeSet(), kOrigin, 0, std::size_t(64) << 20);
    int frames = 0;
    const BuildingCut cut = converge(s, v, nullptr, &frames);
    EXPECT_EQ(cut.tiles, visibleTiles(v));
    EXPECT_FALSE(cut.budgetLimited);
    EXPECT_GT(frames, 2);
  }
  // The low views see part of the town only.
  EXPECT_LT(visibleTiles(lowWest()).size(), std::size_t(kTiles * kTiles) / 2);
  EXPECT_EQ(visibleTiles(aerial()).size(), std::size_t(kTiles * kTiles));
}

TEST(BuildingStream, AReachKeepsOnlyTheTilesWithinItThatTheViewMaySee) {
  const View v = lowWest();
  const double reach = 120.0;
  std::vector<std::uint32_t> expected;
  for (std::uint32_t t : visibleTiles(v)) {
    const Aabb b = tileData(t).mesh.bounds();
    const glm::vec3 lo(b.lo - kOrigin), hi(b.hi - kOrigin);  // as the stream keeps them
    const glm::dvec3 eye = v.camera.center - kOrigin;
    const glm::dvec3 d = glm::max(glm::max(glm::dvec3(lo) - eye, eye - glm::dvec3(hi)), glm::dvec3(0.0));
    if (glm::length(d) <= reach) expected.push_back(t);
  }
  ASSERT_GT(expected.size(), 1u);
  ASSERT_LT(expected.size(), visibleTiles(v).size());
  auto reads = std::make_shared<std::atomic<int>>(0);
  BuildingStream s(makeSet(reads), kOrigin, 0, std::size_t(64) << 20);
  BuildingCut cut;
  for (int f = 0; f < 1000; ++f) {
    s.beginFrame();
    s.poll();
    cut = s.select(v.camera, v.clip, 0.0, reach);
    s.endFrame();
    if (cut.missing == 0 && s.pendingTiles() == 0) break;
  }
  EXPECT_EQ(cut.tiles, expected);
  // Nothing far beyond the reach was read (the source's boxes are a cell wider each side).
  EXPECT_LT(*reads, int(visibleTiles(v).size()));
}

TEST(BuildingStream, TheTilesTogetherAreEveryBuildingOnceWithItsValidity) {
  BuildingStream s(makeSet(), kOrigin, 0, std::size_t(64) << 20);
  std::map<std::uint32_t, BuildingTileMesh> got;
  converge(s, aerial(), &got);
  ASSERT_EQ(got.size(), std::size_t(kTiles * kTiles));
  std::size_t triangles = 0, buildings = 0;
  std::set<int> indices;
  for (const auto& [t, m] : got) {
    const BuildingTileData d = tileData(t);
    triangles += m.indices.size() / 3;
    buildings += d.validity.size();
    ASSERT_EQ(m.validity.size(), d.validity.size());
    ASSERT_EQ(m.vertices.size(), d.mesh.positions.size() * GeometryBuffers::kStride);
    for (std::size_t v = 0; v < d.mesh.positions.size(); ++v) {
      const float* p = &m.vertices[v * GeometryBuffers::kStride];
      const glm::dvec3 r = d.mesh.positions[v] - kOrigin;
      EXPECT_EQ(p[0], float(r.x));
      EXPECT_EQ(p[2], float(r.z));
      const int index = int(p[5]) - 1;  // building index + 1
      const std::uint32_t local = std::uint32_t(index) - m.firstBuilding;
      ASSERT_LT(local, d.validity.size());
      const glm::vec2 days = ibr::gpuDays(d.validity[local]);
      EXPECT_EQ(p[3], days.x);
      EXPECT_EQ(p[4], days.y);
      indices.insert(index);
    }
  }
  std::size_t expected = 0, expectedBuildings = 0;
  for (std::uint32_t t = 0; t < kTiles * kTiles; ++t)
    expected += tileData(t).mesh.triangles.size(), expectedBuildings += tileData(t).validity.size();
  EXPECT_EQ(triangles, expected);
  EXPECT_EQ(buildings, expectedBuildings);
  EXPECT_EQ(indices.size(), expectedBuildings) << "one building index per building";
  EXPECT_EQ(s.buildingIndexEnd(), expectedBuildings);
  EXPECT_EQ(s.residentBuildings(), expectedBuildings);
}

TEST(BuildingStream, LruKeepsTheBudgetAndTheSameViewConvergesAgain) {
  // Find a view's bytes, then a budget that holds one view and not both.
  std::size_t westBytes = 0, eastBytes = 0;
  {
    BuildingStream s(makeSet(), kOrigin, 0, std::size_t(64) << 20);
    converge(s, lowWest());
    westBytes = s.residentBytes();
    BuildingStream e(makeSet(), kOrigin, 0, std::size_t(64) << 20);
    converge(e, lowEast());
    eastBytes = e.residentBytes();
  }
  const std::size_t budget = std::max(westBytes, eastBytes) + 16;
  ASSERT_LT(budget, westBytes + eastBytes);
  BuildingStream s(makeSet(), kOrigin, 0, budget);
  const BuildingCut west = converge(s, lowWest());
  EXPECT_EQ(west.tiles, visibleTiles(lowWest()));
  EXPECT_EQ(converge(s, lowEast()).tiles, visibleTiles(lowEast()));
  EXPECT_GT(s.evictions(), 0u);
  EXPECT_LE(s.peakBytes(), budget + eastBytes);  // arrivals may overshoot until the frame's end
  EXPECT_EQ(converge(s, lowWest()), west);
  EXPECT_LE(s.residentBytes(), budget);
  // Freed building indices are given again: the index space stays near what is resident.
  EXPECT_LE(s.buildingIndexEnd(), 2 * s.residentBuildings() + 8);
  // A share reserved by the terrain leaves less for the buildings: the cut is limited, not over.
  const std::size_t cutBytes = s.frameBytes();  // the converged west cut's
  ASSERT_GT(cutBytes, 0u);
  const std::size_t reserved = budget - cutBytes / 2;
  s.beginFrame(reserved);
  const BuildingCut limited = s.select(lowWest().camera, lowWest().clip, 0.0);
  EXPECT_TRUE(limited.budgetLimited);
  EXPECT_LE(s.frameBytes() + reserved, budget);
  EXPECT_LT(limited.tiles.size(), west.tiles.size());
  EXPECT_GT(limited.tiles.size(), 0u);
  s.endFrame(reserved);
  EXPECT_LE(s.residentBytes() + reserved, budget);
}

TEST(BuildingStream, TwoThreadsGiveWhatNoThreadGives) {
  std::map<std::uint32_t, BuildingTileMesh> a, b;
  BuildingStream s0(makeSet(), kOrigin, 0, std::size_t(64) << 20);
  BuildingStream s2(makeSet(), kOrigin, 2, std::size_t(64) << 20);
  EXPECT_EQ(s2.workerThreads(), 2);
  const BuildingCut c0 = converge(s0, lowEast(), &a);
  const BuildingCut c2 = converge(s2, lowEast(), &b);
  EXPECT_EQ(c0, c2);
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [t, m] : a) {
    const BuildingTileMesh& n = b.at(t);
    ASSERT_EQ(m.vertices.size(), n.vertices.size());
    EXPECT_EQ(m.indices, n.indices);
    for (std::size_t i = 0; i < m.vertices.size(); ++i) {
      // The building index depends on the arrival order: compared relative to the tile's first.
      if (i % GeometryBuffers::kStride == 5)
        EXPECT_EQ(m.vertices[i] - float(m.firstBuilding), n.vertices[i] - float(n.firstBuilding));
      else
        EXPECT_EQ(m.vertices[i], n.vertices[i]);
    }
  }
  // waitAll hands everything over at once.
  BuildingStream w(makeSet(), kOrigin, 2, std::size_t(64) << 20);
  w.beginFrame();
  const int missing = w.select(aerial().camera, aerial().clip, 0.0).missing;
  int got = 0;
  w.waitAll([&](BuildingTileMesh&&) { ++got; });
  EXPECT_EQ(got, missing);
  EXPECT_EQ(w.pendingTiles(), 0u);
}

TEST(BuildingStream, BoxPixelExtentIsTheCornersRectangle) {
  // A camera at the origin looking along +x, 500 px of focal length: a metre at 100 m is 5 px.
  const Camera c = lookAtCamera("c", {0.0, 0.0, 0.0}, {100.0, 0.0, 0.0}, 640, 480, 500.0);
  // 20 m wide, 5 m tall, 100 m deep from 100 m on: its near face is the widest and the tallest.
  const glm::dvec2 e = boxPixelExtent(c, {100.0, -10.0, 0.0}, {200.0, 10.0, 5.0});
  EXPECT_NEAR(e.x, 100.0, 1e-9);
  EXPECT_NEAR(e.y, 25.0, 1e-9);
  // Twice as far, half the size.
  const glm::dvec2 far = boxPixelExtent(c, {200.0, -10.0, 0.0}, {300.0, 10.0, 5.0});
  EXPECT_NEAR(far.x, 50.0, 1e-9);
  EXPECT_NEAR(far.y, 12.5, 1e-9);
  // A box reaching the camera's plane, or behind it: unbounded.
  EXPECT_TRUE(std::isinf(boxPixelExtent(c, {-1.0, -1.0, -1.0}, {50.0, 1.0, 1.0}).x));
  EXPECT_TRUE(std::isinf(boxPixelExtent(c, {-50.0, -1.0, -1.0}, {-10.0, 1.0, 1.0}).y));
}

TEST(BuildingStream, AMinimumPictureSizeLeavesOutTheThinTiles) {
  const View v = lowWest();
  // Each visible tile's thickness in the view, from its buildings' box (as the stream keeps it
  // once read, in floats of the render frame) through Camera::project.
  std::vector<std::pair<double, std::uint32_t>> thick;
  for (std::uint32_t t : visibleTiles(v)) {
    const Aabb b = tileData(t).mesh.bounds();
    const glm::dvec3 lo = glm::dvec3(glm::vec3(b.lo - kOrigin)) + kOrigin;
    const glm::dvec3 hi = glm::dvec3(glm::vec3(b.hi - kOrigin)) + kOrigin;
    glm::dvec2 pmin(1e300), pmax(-1e300);
    bool inFront = true;  // else it reaches the camera's plane: kept whatever the threshold
    for (int k = 0; k < 8; ++k) {
      const Projection p = v.camera.project({k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z});
      inFront = inFront && p.depth > 0.0;
      pmin = glm::min(pmin, p.pxIdeal);
      pmax = glm::max(pmax, p.pxIdeal);
    }
    thick.push_back({inFront ? std::min(pmax.x - pmin.x, pmax.y - pmin.y) : 1e300, t});
  }
  std::sort(thick.begin(), thick.end());
  ASSERT_GT(thick.size(), 4u);
  // A threshold between the thinnest half and the rest.
  const std::size_t half = thick.size() / 2;
  ASSERT_LT(thick[half - 1].first + 1e-3, thick[half].first);
  const double minPixels = 0.5 * (thick[half - 1].first + thick[half].first);
  std::vector<std::uint32_t> expected;
  for (std::size_t i = half; i < thick.size(); ++i) expected.push_back(thick[i].second);
  std::sort(expected.begin(), expected.end());

  BuildingStream s(makeSet(), kOrigin, 0, std::size_t(64) << 20);
  BuildingCut cut;
  for (int f = 0; f < 1000; ++f) {
    s.beginFrame();
    s.poll();
    cut = s.select(v.camera, v.clip, 0.0, std::numeric_limits<double>::infinity(), minPixels);
    s.endFrame();
    if (cut.missing == 0 && s.pendingTiles() == 0) break;
  }
  EXPECT_EQ(cut.tiles, expected);
  // 0: every tile the view may see, as without the argument.
  BuildingStream all(makeSet(), kOrigin, 0, std::size_t(64) << 20);
  EXPECT_EQ(converge(all, v).tiles, visibleTiles(v));
}

TEST(BuildingStream, ABrokenTileIsReportedOnceAndNotAskedAgain) {
  auto set = makeSet();
  auto reads = std::make_shared<std::atomic<int>>(0);
  set->read = [reads](std::uint32_t t) {
    if (t == 0) {
      ++*reads;
      throw std::runtime_error("city.gpkg: tile 0: I/O error");
    }
    return tileData(t);
  };
  BuildingStream s(set, kOrigin, 0, std::size_t(64) << 20);
  s.setRetryPolicy({std::chrono::milliseconds(0), std::chrono::milliseconds(0), 1});  // one read, no retry
  std::vector<std::string> errors;
  for (int f = 0; f < 200; ++f) {
    s.beginFrame();
    for (const BuildingTileMesh& m : s.poll())
      if (!m.error.empty()) errors.push_back(m.error);
    s.select(lowWest().camera, lowWest().clip, 0.0);
    s.endFrame();
  }
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("I/O error"), std::string::npos);
  EXPECT_EQ(*reads, 1);
  EXPECT_EQ(s.brokenTiles(), 1u);
  EXPECT_THROW(BuildingStream(nullptr, kOrigin, 0, 1), std::invalid_argument);
  EXPECT_THROW(BuildingStream(set, kOrigin, -1, 1), std::invalid_argument);
  EXPECT_THROW(BuildingStream(set, kOrigin, 0, 0), std::invalid_argument);
}

// A source that fails tile 0 its first `failures` reads (a service answering 500, then recovering).
std::shared_ptr<BuildingTileSet> flakySet(int failures, std::shared_ptr<std::atomic<int>> reads) {
  auto set = makeSet();
  set->source = "WFS:http://127.0.0.1:1/buildings";
  set->read = [reads, failures](std::uint32_t t) {
    if (t == 0 && ++*reads <= failures) throw std::runtime_error("HTTP error code : 500");
    return tileData(t);
  };
  return set;
}

// Frames until nothing is pending, the tiles' results handed to `sink`.
void frames(BuildingStream& s, int n, const std::function<void(const BuildingTileMesh&)>& sink) {
  for (int f = 0; f < n; ++f) {
    s.beginFrame();
    for (const BuildingTileMesh& m : s.poll()) sink(m);
    s.select(lowWest().camera, lowWest().clip, 0.0);
    s.endFrame();
  }
}

TEST(BuildingStream, ATileThatFailedIsReadAgainAndArrives) {
  auto reads = std::make_shared<std::atomic<int>>(0);
  BuildingStream s(flakySet(2, reads), kOrigin, 0, std::size_t(64) << 20);
  s.setRetryPolicy({std::chrono::milliseconds(0), std::chrono::milliseconds(0), 6});  // again at once
  std::vector<BuildingTileMesh> tile0;
  frames(s, 300, [&](const BuildingTileMesh& m) {
    if (m.tile == 0) tile0.push_back(m);
  });
  ASSERT_EQ(tile0.size(), 3u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(tile0[size_t(i)].attempt, i + 1);
    EXPECT_TRUE(tile0[size_t(i)].retrying);
    EXPECT_EQ(tile0[size_t(i)].error, "WFS:http://127.0.0.1:1/buildings: tile 0: HTTP error code : 500");
  }
  EXPECT_TRUE(tile0[2].error.empty());
  EXPECT_EQ(tile0[2].attempt, 3);
  EXPECT_FALSE(tile0[2].indices.empty());
  EXPECT_EQ(*reads, 3);
  EXPECT_EQ(s.brokenTiles(), 0u);
  EXPECT_EQ(s.retryingTiles(), 0u);
  glm::vec3 lo, hi;
  EXPECT_TRUE(s.boxOf(0, lo, hi));
}

TEST(BuildingStream, ATileFailingEveryTimeIsGivenUpAfterTheAttempts) {
  auto reads = std::make_shared<std::atomic<int>>(0);
  BuildingStream s(flakySet(1000, reads), kOrigin, 0, std::size_t(64) << 20);
  s.setRetryPolicy({std::chrono::milliseconds(0), std::chrono::milliseconds(0), 3});
  std::vector<BuildingTileMesh> tile0;
  frames(s, 300, [&](const BuildingTileMesh& m) {
    if (m.tile == 0) tile0.push_back(m);
  });
  ASSERT_EQ(tile0.size(), 3u);
  EXPECT_EQ(*reads, 3);
  EXPECT_TRUE(tile0[0].retrying);
  EXPECT_TRUE(tile0[1].retrying);
  EXPECT_FALSE(tile0[2].retrying) << "the last try is given up";
  EXPECT_EQ(s.brokenTiles(), 1u);
  EXPECT_EQ(s.retryingTiles(), 0u);
}

TEST(BuildingStream, ATileWaitingForItsNextTryIsNeitherAskedNorWaitedFor) {
  auto reads = std::make_shared<std::atomic<int>>(0);
  BuildingStream s(flakySet(1, reads), kOrigin, 0, std::size_t(64) << 20);
  s.setRetryPolicy({std::chrono::hours(1), std::chrono::hours(2), 6});  // not again within the test
  int errors = 0;
  frames(s, 300, [&](const BuildingTileMesh& m) { errors += !m.error.empty(); });
  EXPECT_EQ(errors, 1);
  EXPECT_EQ(*reads, 1);
  EXPECT_EQ(s.retryingTiles(), 1u);
  EXPECT_EQ(s.brokenTiles(), 0u);
  EXPECT_EQ(s.pendingTiles(), 0u);
}

}  // namespace
}  // namespace hv::render
