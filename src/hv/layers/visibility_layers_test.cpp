#include "hv/layers/visibility_layers.h"

#include "hv/layers/object_layers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>

namespace hv::layers {
namespace {

// A scene drawn in characters: one string per pixel row, per pixel the objects along the ray
// nearest first ("AB": A, then B behind it; "." or "": nothing). Depths are the positions.
PixelHits fromRows(const std::vector<std::vector<std::string>>& rows) {
  PixelHits h;
  h.height = int(rows.size());
  h.width = rows.empty() ? 0 : int(rows[0].size());
  for (const auto& row : rows)
    for (const std::string& ray : row) {
      std::vector<SurfaceHit> hits;
      for (std::size_t k = 0; k < ray.size(); ++k)
        if (ray[k] != '.') hits.push_back({std::uint32_t(ray[k] - 'A'), double(k + 1)});
      h.appendPixel(hits);
    }
  return h;
}

std::vector<std::uint32_t> ids(const std::string& letters) {
  std::vector<std::uint32_t> v;
  for (char c : letters) v.push_back(std::uint32_t(c - 'A'));
  return v;
}

TEST(VisibilityLayers, BuildingBehindAnother) {
  // A in front, B behind it on the middle rays and seen beside it; G the ground behind both.
  const PixelHits h = fromRows({{"BG", "ABG", "ABG", "AG", "G"}, {"BG", "BG", "ABG", "AG", "G"}});
  const VisibilityLayers v = peelVisibilityLayers(h);
  ASSERT_EQ(v.layers.size(), 3u);
  EXPECT_EQ(v.layers[0].objects, ids("A"));
  EXPECT_EQ(v.layers[1].objects, ids("B"));
  EXPECT_EQ(v.layers[2].objects, ids("G"));
  EXPECT_TRUE(v.cycles.empty());
  // Layer 2 at pixel (1, 0) is B's hit, behind A.
  const std::int64_t i = v.hitOfLayer(h, 1, 2);
  ASSERT_GE(i, 0);
  EXPECT_EQ(h.hits[std::size_t(i)].object, 1u);
  EXPECT_DOUBLE_EQ(h.hits[std::size_t(i)].depth, 2.0);
  EXPECT_EQ(v.hitOfLayer(h, 4, 1), -1);  // nothing of A on the last ray
}

TEST(VisibilityLayers, SelfOcclusionDoesNotBlock) {
  // An L-shaped building L seen so that its near wing hides its far wing ("LL"), in front of B.
  const PixelHits h = fromRows({{"L", "LL", "LLB", "LB", "B"}});
  const VisibilityLayers v = peelVisibilityLayers(h);
  ASSERT_EQ(v.layers.size(), 2u);
  EXPECT_EQ(v.layers[0].objects, ids("L"));
  EXPECT_EQ(v.layers[1].objects, ids("B"));
}

TEST(VisibilityLayers, Courtyard) {
  // A building C around a courtyard, on the ground T (front-facing surfaces only, as the ray caster
  // keeps them): the street ("T"), the outer wall hiding the courtyard's ground ("CT"), the outer
  // wall hiding the lower part of the courtyard's far wall, then the ground behind the building
  // ("CCT"), the courtyard seen from above ("T"), the far wall seen over the front one ("C").
  const PixelHits h = fromRows({{"T", "CT", "CCT", "T", "C", "CT"}});
  const VisibilityLayers v = peelVisibilityLayers(h);
  ASSERT_EQ(v.layers.size(), 2u);
  EXPECT_EQ(v.layers[0].objects, ids("C"));  // its own far wall behind its front wall does not block it
  EXPECT_EQ(v.layers[1].objects, ids("T"));
  EXPECT_TRUE(v.cycles.empty());
  // Peeling order matches the per-ray order: along every ray, layers never decrease.
  for (std::size_t p = 0; p < h.pixelCount(); ++p)
    for (std::uint32_t i = h.first[p]; i + 1 < h.first[p + 1]; ++i) EXPECT_LE(v.layerOfHit[i], v.layerOfHit[i + 1]);
}

TEST(VisibilityLayers, ShedInACourtyardIsACycleOfTwo) {
  // A shed S inside C's courtyard: C's outer wall hides part of S ("CS"), S hides part of the
  // courtyard's far wall ("SC"). Neither can be taken whole: a cycle, split at pixel level.
  const PixelHits h = fromRows({{"CS", "SC", "C", "CC", "S"}});
  const VisibilityLayers v = peelVisibilityLayers(h);
  ASSERT_EQ(v.cycles.size(), 1u);
  EXPECT_EQ(std::set<std::uint32_t>(v.cycles[0].begin(), v.cycles[0].end()), (std::set<std::uint32_t>{2, 18}));
  ASSERT_EQ(v.layers.size(), 2u);
  EXPECT_EQ(v.layerOfHit[0], 1);  // C's outer wall, in front
  EXPECT_EQ(v.layerOfHit[1], 2);  // the part of S it hides
  EXPECT_EQ(v.layerOfHit[2], 1);  // S where it is in front
  EXPECT_EQ(v.layerOfHit[3], 2);  // the part of the far wall S hides
}

TEST(VisibilityLayers, TwoIndependentObjectsShareALayer) {
  const PixelHits h = fromRows({{"AG", "G", "BG"}});
  const VisibilityLayers v = peelVisibilityLayers(h);
  ASSERT_EQ(v.layers.size(), 2u);
  EXPECT_EQ(v.layers[0].objects, ids("AB"));
}

TEST(VisibilityLayers, CycleOfThreeIsReportedAndSplit) {
  // Three planks overlapping in a ring: A over B, B over C, C over A, each also seen alone.
  const PixelHits h = fromRows({{"AB", "BC", "CA", "A", "B", "C"}});
  const VisibilityLayers v = peelVisibilityLayers(h);
  ASSERT_EQ(v.cycles.size(), 1u);
  const auto& cycle = v.cycles[0];
  ASSERT_EQ(cycle.size(), 3u);
  EXPECT_EQ(std::set<std::uint32_t>(cycle.begin(), cycle.end()), (std::set<std::uint32_t>{0, 1, 2}));
  // Occlusion order: each hides the next (A hides B, B hides C, C hides A).
  for (std::size_t k = 0; k < 3; ++k) {
    const std::uint32_t a = cycle[k], b = cycle[(k + 1) % 3];
    EXPECT_EQ((b + 3 - a) % 3, 1u) << "object " << a << " is not in front of object " << b;
  }
  // Split: layer 1 takes each plank where it is in front, layer 2 the parts hidden.
  ASSERT_EQ(v.layers.size(), 2u);
  EXPECT_EQ(v.layers[0].objects, ids("ABC"));
  EXPECT_EQ(v.layers[0].split, ids("ABC"));
  EXPECT_EQ(v.layers[1].objects, ids("ABC"));
  EXPECT_TRUE(v.layers[1].split.empty());
  const std::int64_t hidden = v.hitOfLayer(h, 0, 2);  // B behind A
  ASSERT_GE(hidden, 0);
  EXPECT_EQ(h.hits[std::size_t(hidden)].object, 1u);
  for (std::size_t i = 0; i < h.hits.size(); ++i) EXPECT_NE(v.layerOfHit[i], 0);
}

TEST(VisibilityLayers, CycleBehindAnOccluder) {
  // The ring of three behind a front object F: F first, then the cycle is met and split.
  const PixelHits h = fromRows({{"FAB", "BC", "CA", "FA", "B", "C"}});
  const VisibilityLayers v = peelVisibilityLayers(h);
  ASSERT_GE(v.layers.size(), 3u);
  EXPECT_EQ(v.layers[0].objects, ids("F"));
  EXPECT_EQ(v.cycles.size(), 1u);
}

TEST(VisibilityLayers, CompletedFromObjectLayersMatchesThePeel) {
  // F over the ring of three: given F in layer 1 (and object H, on no ray, in layer 2: dropped),
  // the ring is found and split after it, as the whole peel does.
  const PixelHits h = fromRows({{"FAB", "BC", "CA", "FA", "B", "C"}});
  const VisibilityLayers whole = peelVisibilityLayers(h);
  std::vector<std::uint16_t> given(8, 0);
  given[5] = 1;  // F
  given[7] = 2;  // H
  const VisibilityLayers v = completeVisibilityLayers(h, given);
  EXPECT_EQ(v.layerOfHit, whole.layerOfHit);
  ASSERT_EQ(v.layers.size(), whole.layers.size());
  for (std::size_t k = 0; k < v.layers.size(); ++k) {
    EXPECT_EQ(v.layers[k].objects, whole.layers[k].objects) << "layer " << k + 1;
    EXPECT_EQ(v.layers[k].split, whole.layers[k].split) << "layer " << k + 1;
  }
  EXPECT_EQ(v.cycles, whole.cycles);
  // Every object given: nothing left to peel, the layers as given.
  const PixelHits simple = fromRows({{"ABG", "BG", "G"}});
  const VisibilityLayers s = completeVisibilityLayers(simple, {1, 2, 0, 0, 0, 0, 3});
  ASSERT_EQ(s.layers.size(), 3u);
  EXPECT_EQ(s.layers[2].objects, ids("G"));
  EXPECT_EQ(s.layerOfHit, (std::vector<std::uint16_t>{1, 2, 3, 2, 3, 3}));
}

// Rays given with the triangles hit: per pixel (one row), (object, triangle) nearest first, depths
// the positions; faceOfTriangle as given.
PixelHits withTriangles(const std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>>& rays,
                        std::vector<std::uint32_t> faceOfTriangle) {
  PixelHits h;
  h.width = int(rays.size());
  h.height = 1;
  h.faceOfTriangle = std::move(faceOfTriangle);
  for (const auto& ray : rays) {
    std::vector<SurfaceHit> hits;
    for (std::size_t k = 0; k < ray.size(); ++k) hits.push_back({ray[k].first, double(k + 1), ray[k].second});
    h.appendPixel(hits);
  }
  return h;
}

TEST(VisibilityLayers, RingOfThreeIsSplitIntoFaces) {
  // A (0), B (1), C (2), two faces each of one triangle (triangle t is face t: A 0, 1; B 2, 3;
  // C 4, 5). A's face 0 hides B's face 3, B's face 2 hides C's face 5, C's face 4 hides A's face 1:
  // whole, a ring; as faces, 0, 2 and 4 hide the others and nothing hides them.
  const PixelHits h = withTriangles(
      {{{0, 0}, {1, 3}}, {{1, 2}, {2, 5}}, {{2, 4}, {0, 1}}, {{0, 0}}, {{1, 2}}, {{2, 4}}}, {0, 1, 2, 3, 4, 5});
  const VisibilityLayers v = peelVisibilityLayers(h);
  EXPECT_TRUE(v.cycles.empty());  // nothing broken at pixel level
  ASSERT_EQ(v.splits.size(), 1u);
  EXPECT_EQ(v.splits[0].into, CycleSplit::Into::Faces);
  EXPECT_EQ(v.splits[0].items, 3u);
  EXPECT_EQ(v.splits[0].beforeLayer, 1);
  const auto& cycle = v.splits[0].objects;
  ASSERT_EQ(cycle.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k)
    EXPECT_EQ((cycle[(k + 1) % 3] + 3 - cycle[k]) % 3, 1u) << "object " << cycle[k] << " does not hide the next";
  EXPECT_EQ(v.layerOfHit, (std::vector<std::uint16_t>{1, 2, 1, 2, 1, 2, 1, 1, 1}));
  ASSERT_EQ(v.layers.size(), 2u);
  EXPECT_EQ(v.layers[0].objects, ids("ABC"));
  EXPECT_EQ(v.layers[0].split, ids("ABC"));
  EXPECT_EQ(v.layers[1].split, ids("ABC"));
  EXPECT_EQ(v.splitObjects, ids("ABC"));
  EXPECT_TRUE(v.splitFaces.empty());
  EXPECT_EQ(v.pieceOf(h, h.hits[1]), (VisibilityLayers::Piece{VisibilityLayers::PieceKind::Face, 3}));
}

TEST(VisibilityLayers, FacesStillInACycleAreSplitIntoTriangles) {
  // One face per object, of two triangles (A: 0, 1 face 0; B: 2, 3 face 1; C: 4, 5 face 2).
  // Triangle 1 hides 2, 3 hides 4, 5 hides 0: the faces are a ring as the objects are; the
  // triangles are not (1, 3, 5 first, then 0, 2, 4).
  const PixelHits h = withTriangles(
      {{{0, 1}, {1, 2}}, {{1, 3}, {2, 4}}, {{2, 5}, {0, 0}}, {{0, 0}}, {{1, 2}}, {{2, 4}}}, {0, 0, 1, 1, 2, 2});
  const VisibilityLayers v = peelVisibilityLayers(h);
  EXPECT_TRUE(v.cycles.empty());
  ASSERT_EQ(v.splits.size(), 2u);
  EXPECT_EQ(v.splits[0].into, CycleSplit::Into::Faces);
  EXPECT_EQ(v.splits[1].into, CycleSplit::Into::Triangles);
  EXPECT_EQ(v.splits[1].items, 3u);  // the three faces
  EXPECT_EQ(v.splits[1].beforeLayer, 1);
  EXPECT_EQ(v.layerOfHit, (std::vector<std::uint16_t>{1, 2, 1, 2, 1, 2, 2, 2, 2}));
  ASSERT_EQ(v.layers.size(), 2u);
  EXPECT_EQ(v.splitFaces, (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_EQ(v.pieceOf(h, h.hits[0]), (VisibilityLayers::Piece{VisibilityLayers::PieceKind::Triangle, 1}));
}

TEST(VisibilityLayers, CyclicTrianglesAreReportedAndBrokenAtPixelLevel) {
  // Two single-triangle objects crossing each other: A (triangle 0) in front of B (triangle 1) on
  // the first ray, behind it on the second. No split orders them: a cycle, broken at pixel level.
  const PixelHits h = withTriangles({{{0, 0}, {1, 1}}, {{1, 1}, {0, 0}}, {{0, 0}}, {{1, 1}}}, {0, 1});
  const VisibilityLayers v = peelVisibilityLayers(h);
  ASSERT_EQ(v.splits.size(), 3u);
  EXPECT_EQ(v.splits[0].into, CycleSplit::Into::Faces);
  EXPECT_EQ(v.splits[1].into, CycleSplit::Into::Triangles);
  EXPECT_EQ(v.splits[2].into, CycleSplit::Into::Pixels);
  ASSERT_EQ(v.cycles.size(), 1u);
  EXPECT_EQ(std::set<std::uint32_t>(v.cycles[0].begin(), v.cycles[0].end()), (std::set<std::uint32_t>{0, 1}));
  EXPECT_EQ(v.layerOfHit, (std::vector<std::uint16_t>{1, 2, 1, 2, 1, 1}));
  ASSERT_EQ(v.layers.size(), 2u);
  EXPECT_EQ(v.layers[0].split, ids("AB"));
}

TEST(VisibilityLayers, SplitCompletedFromObjectLayersMatchesThePeel) {
  // F (3, triangle 6) in front of the faces' ring: F first, the ring split into faces after it.
  const PixelHits h =
      withTriangles({{{3, 6}, {0, 0}, {1, 3}}, {{1, 2}, {2, 5}}, {{2, 4}, {0, 1}}, {{0, 0}}, {{1, 2}}, {{2, 4}}},
                    {0, 1, 2, 3, 4, 5, 6});
  const VisibilityLayers whole = peelVisibilityLayers(h);
  ASSERT_EQ(whole.layers.size(), 3u);
  EXPECT_EQ(whole.layers[0].objects, ids("D"));
  ASSERT_EQ(whole.splits.size(), 1u);
  EXPECT_EQ(whole.splits[0].beforeLayer, 2);
  const VisibilityLayers v = completeVisibilityLayers(h, {0, 0, 0, 1});
  EXPECT_EQ(v.layerOfHit, whole.layerOfHit);
  ASSERT_EQ(v.splits.size(), 1u);
  EXPECT_EQ(v.splits[0].objects, whole.splits[0].objects);
  EXPECT_EQ(v.splitObjects, whole.splitObjects);
}

TEST(VisibilityLayers, HitWithoutItsTriangleIsRefused) {
  PixelHits h;
  h.width = 1;
  h.height = 1;
  h.faceOfTriangle = {0, 0};
  h.appendPixel({{0, 1.0}});  // no triangle named
  try {
    peelVisibilityLayers(h);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("names triangle none"), std::string::npos) << e.what();
  }
}

TEST(VisibilityLayers, EmptyAndInconsistentInput) {
  PixelHits empty;
  empty.width = 2;
  empty.height = 1;
  empty.appendPixel({});
  empty.appendPixel({});
  EXPECT_TRUE(peelVisibilityLayers(empty).layers.empty());
  PixelHits bad;
  bad.width = 3;
  bad.height = 3;
  try {
    peelVisibilityLayers(bad);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("3 x 3"), std::string::npos) << e.what();
  }
}

TEST(VisibilityLayers, UnsortedPixelHitsAreSorted) {
  PixelHits h;
  h.width = 2;
  h.height = 1;
  h.appendPixel({{1, 5.0}, {0, 2.0}});  // A (0) is nearer although listed second
  h.appendPixel({{1, 1.0}});
  const VisibilityLayers v = peelVisibilityLayers(h);
  ASSERT_EQ(v.layers.size(), 2u);
  EXPECT_EQ(v.layers[0].objects, std::vector<std::uint32_t>{0});
}

}  // namespace
}  // namespace hv::layers
