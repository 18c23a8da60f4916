// Chunk organisation and per-frame chunk selection against brute force on synthetic clouds, and
// load + organise times on the real lidar (delft, autzen) when ../shared/data is there.
#include "hv/scene/chunks.h"

#include "hv/io/native/las_reader.h"
#include "hv/testing/data_dir.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <set>

namespace hv {
namespace {

// A 200 m x 150 m street scene: ground every 0.5 m plus a few walls, deterministic.
PointCloud syntheticCity() {
  PointCloud c;
  c.resize(0, {.intensity = true});
  for (int i = 0; i < 400; ++i)
    for (int j = 0; j < 300; ++j) {
      c.positions.push_back({651000.0 + 0.5 * i, 6862000.0 + 0.5 * j, 38.0 + 0.01 * (i % 7)});
      c.intensity.push_back(std::uint16_t((i * 300 + j) % 65536));
    }
  for (int w = 0; w < 8; ++w)
    for (int i = 0; i < 100; ++i)
      for (int k = 0; k < 40; ++k) {
        c.positions.push_back({651010.0 + 25.0 * w, 6862020.0 + 0.3 * i, 38.0 + 0.5 * k});
        c.intensity.push_back(7);
      }
  return c;
}

TEST(PointChunks, PartitionAndPermuteConsistently) {
  PointCloud c = syntheticCity();
  const std::size_t n = c.size();
  std::vector<std::pair<glm::dvec3, std::uint16_t>> before;
  for (std::size_t i = 0; i < n; ++i) before.emplace_back(c.positions[i], c.intensity[i]);
  organizeChunks(c, {.maxPointsPerChunk = 5000});
  ASSERT_EQ(c.size(), n);
  std::uint32_t next = 0;
  for (const PointChunk& ch : c.chunks) {
    EXPECT_EQ(ch.first, next);
    EXPECT_GT(ch.count, 0u);
    EXPECT_LE(ch.count, 5000u);
    next += ch.count;
    for (std::uint32_t i = ch.first; i < ch.first + ch.count; ++i) {
      EXPECT_TRUE(glm::all(glm::greaterThanEqual(c.positions[i], ch.bounds.lo)));
      EXPECT_TRUE(glm::all(glm::lessThanEqual(c.positions[i], ch.bounds.hi)));
    }
  }
  EXPECT_EQ(next, n);
  EXPECT_GE(c.chunks.size(), n / 5000);
  // The same points with the same attributes, only reordered.
  std::vector<std::pair<glm::dvec3, std::uint16_t>> after;
  for (std::size_t i = 0; i < n; ++i) after.emplace_back(c.positions[i], c.intensity[i]);
  auto less = [](const auto& a, const auto& b) {
    return std::tie(a.first.x, a.first.y, a.first.z, a.second) < std::tie(b.first.x, b.first.y, b.first.z, b.second);
  };
  std::sort(before.begin(), before.end(), less);
  std::sort(after.begin(), after.end(), less);
  EXPECT_TRUE(before == after);
}

TEST(PointChunks, PrefixIsAUniformSubsample) {
  PointCloud c = syntheticCity();
  organizeChunks(c, {.maxPointsPerChunk = 20000});
  for (const PointChunk& ch : c.chunks) {
    // The first 5 % of the chunk spans its extent and its mean is near the chunk's mean: with
    // k >= 500 random points the mean's standard error is below 1/sqrt(12 k) < 1.3 % of the
    // extent; 5 % is about four standard errors.
    const std::uint32_t k = std::max<std::uint32_t>(ch.count / 20, 1);
    if (k < 500) continue;
    Aabb prefix;
    glm::dvec3 meanPrefix(0.0), meanAll(0.0);
    for (std::uint32_t i = 0; i < ch.count; ++i) {
      if (i < k) {
        prefix.extend(c.positions[ch.first + i]);
        meanPrefix += c.positions[ch.first + i] / double(k);
      }
      meanAll += c.positions[ch.first + i] / double(ch.count);
    }
    for (int a = 0; a < 2; ++a) {
      const double extent = ch.bounds.size()[a];
      if (extent < 1.0) continue;
      EXPECT_GT(prefix.size()[a], 0.8 * extent);
      EXPECT_LT(std::abs(meanPrefix[a] - meanAll[a]), 0.05 * extent);
    }
  }
}

TEST(PointChunks, SubsampleKeepsAProportionalPrefixOfEachChunk) {
  PointCloud c = syntheticCity();
  organizeChunks(c, {.maxPointsPerChunk = 5000});
  const std::size_t n = 10007;  // not a divisor of anything: the rounding must still add up
  const PointCloud s = subsampleChunks(c, n);
  ASSERT_EQ(s.size(), n);
  ASSERT_TRUE(s.consistent());
  ASSERT_EQ(s.intensity.size(), n);
  std::uint32_t next = 0;
  size_t source = 0;  // the chunk of `c` that chunk k of `s` was taken from
  for (const PointChunk& k : s.chunks) {
    EXPECT_EQ(k.first, next);  // contiguous, in order
    next += k.count;
    // Find the source chunk: the one whose first point this prefix starts with.
    while (source < c.chunks.size() && c.positions[c.chunks[source].first] != s.positions[k.first]) ++source;
    ASSERT_LT(source, c.chunks.size());
    const PointChunk& from = c.chunks[source];
    const double share = double(from.count) * double(n) / double(c.size());
    EXPECT_LE(std::abs(double(k.count) - share), 1.0);
    Aabb b;
    for (std::uint32_t i = 0; i < k.count; ++i) {
      ASSERT_EQ(s.positions[k.first + i], c.positions[from.first + i]);  // the prefix
      EXPECT_EQ(s.intensity[k.first + i], c.intensity[from.first + i]);
      b.extend(s.positions[k.first + i]);
    }
    EXPECT_EQ(b.lo, k.bounds.lo);
    EXPECT_EQ(b.hi, k.bounds.hi);
    ++source;
  }
  EXPECT_EQ(next, n);
  // Nothing to drop: the cloud as it is.
  EXPECT_EQ(subsampleChunks(c, c.size()).positions, c.positions);
  // A cloud not organised yet is organised first.
  EXPECT_EQ(subsampleChunks(syntheticCity(), 1000).size(), 1000u);
  EXPECT_FALSE(subsampleChunks(syntheticCity(), 1000).chunks.empty());
}

TEST(PointChunks, DeterministicForASeed) {
  PointCloud a = syntheticCity(), b = syntheticCity();
  organizeChunks(a);
  organizeChunks(b);
  EXPECT_EQ(a.positions, b.positions);
}

// Every point a view sees (in front of the camera, inside the image) lies in a selected chunk,
// and the budget is spent as documented.
TEST(PointChunks, SelectionIsConservativeAgainstBruteForce) {
  PointCloud c = syntheticCity();
  organizeChunks(c, {.maxPointsPerChunk = 4000});
  const Aabb bounds = c.bounds();
  const std::vector<Camera> views = {
      lookAtCamera("street", {651050, 6862030, 40}, {651120, 6862040, 39}, 320, 240, 250.0),
      lookAtCamera("corner", {650990, 6861990, 45}, {651010, 6862010, 38}, 320, 240, 300.0),
      lookAtCamera("above", {651100, 6862075, 300}, {651100, 6862076, 38}, 160, 120, 200.0),
      lookAtCamera("away", {650990, 6861990, 40}, {650900, 6861900, 40}, 320, 240, 250.0)};
  for (const Camera& view : views) {
    SCOPED_TRACE(view.id);
    const auto all = selectChunks(c, view, ~std::uint64_t(0));
    std::set<std::uint32_t> selected;
    std::uint64_t visiblePoints = 0;
    for (const ChunkDraw& d : all) {
      selected.insert(d.chunk);
      EXPECT_EQ(d.count, c.chunks[d.chunk].count);  // an unlimited budget draws everything
      visiblePoints += d.count;
    }
    std::set<std::uint32_t> seen;
    for (std::uint32_t k = 0; k < c.chunks.size(); ++k)
      for (std::uint32_t i = c.chunks[k].first; i < c.chunks[k].first + c.chunks[k].count; ++i) {
        const Projection p = view.project(c.positions[i]);
        if (p.depth > 0.0 && p.pxIdeal.x >= 0 && p.pxIdeal.x <= view.width && p.pxIdeal.y >= 0 &&
            p.pxIdeal.y <= view.height) {
          seen.insert(k);
          break;
        }
      }
    for (std::uint32_t k : seen) EXPECT_TRUE(selected.count(k)) << "chunk " << k << " is seen but not selected";
    if (view.id == "away") EXPECT_TRUE(seen.empty() && selected.empty());
    if (view.id == "street") EXPECT_LT(selected.size(), c.chunks.size()) << "culling culls";

    // A small budget: spent exactly, near chunks get a larger fraction than far ones.
    const std::uint64_t budget = visiblePoints / 10;
    const auto part = selectChunks(c, view, budget);
    std::uint64_t sum = 0;
    for (const ChunkDraw& d : part) {
      EXPECT_LE(d.count, c.chunks[d.chunk].count);
      sum += d.count;
    }
    EXPECT_LE(sum, budget);
    EXPECT_GE(sum + part.size(), budget);  // at most one point lost per chunk to rounding down
    if (part.size() >= 2) {
      auto fraction = [&](const ChunkDraw& d) { return double(d.count) / c.chunks[d.chunk].count; };
      EXPECT_GE(fraction(part.front()), fraction(part.back()));  // nearest first
    }
    (void)bounds;
  }
}

// Real lidar: load + organise times (printed for docs/performance.md), counts and classes as
// ../shared/data/README.md states them.
TEST(PointChunks, RealLidarLoadsAndOrganisesInSeconds) {
  struct Case {
    const char* dataset;
    const char* file;
    std::size_t points;
  };
  bool any = false;
  for (const Case& k : {Case{"delft", "cloud.las", 848942}, Case{"autzen", "autzen_trim.las", 110000}}) {
    const std::string dir = testing::dataset(k.dataset);
    if (dir.empty()) continue;
    any = true;
    const auto t0 = std::chrono::steady_clock::now();
    PointCloud c = readLas(dir + "/" + k.file);
    const auto t1 = std::chrono::steady_clock::now();
    organizeChunks(c);
    const auto t2 = std::chrono::steady_clock::now();
    const Camera view = lookAtCamera("v", c.bounds().center() + glm::dvec3(0, -150, 60), c.bounds().center(), 1280,
                                     720, 900.0);
    const auto draws = selectChunks(c, view, 1'000'000);
    const auto t3 = std::chrono::steady_clock::now();
    auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
    std::printf("[ points ] %s: %zu points, read %.0f ms, organise %.0f ms (%zu chunks), select %.2f ms (%zu chunks)\n",
                k.dataset, c.size(), ms(t0, t1), ms(t1, t2), c.chunks.size(), ms(t2, t3), draws.size());
    EXPECT_EQ(c.size(), k.points);
    EXPECT_LT(ms(t0, t2), 10000.0) << "load + organise must take seconds at most";
    const auto h = c.classHistogram();
    if (std::string(k.dataset) == "delft") {
      EXPECT_EQ(c.crs, "EPSG:28992");
      EXPECT_EQ(h[1], 282445u);
      EXPECT_EQ(h[2], 283118u);
      EXPECT_EQ(h[6], 280065u);
      EXPECT_EQ(h[9], 835u);
      EXPECT_EQ(h[26], 2479u);
      EXPECT_NEAR(c.bounds().lo.x, 84808.3, 0.05);
      EXPECT_NEAR(c.bounds().hi.y, 447641.3, 0.05);
    } else {
      EXPECT_TRUE(c.fields().rgb);
      EXPECT_NE(c.crs.find("Lambert"), std::string::npos) << c.crs;  // the WKT VLR, preferred
      EXPECT_EQ(h[1], 83893u);
      EXPECT_EQ(h[2], 26107u);
      EXPECT_NEAR(c.bounds().lo.x, 636001.76, 0.005);
      EXPECT_NEAR(c.bounds().hi.z, 520.51, 0.005);
    }
  }
  if (!any) HV_SKIP_WITHOUT_DATA(std::string("no ../shared/data (delft, autzen): real lidar not checked"));
}

}  // namespace
}  // namespace hv
