#include "hv/scene/footprint.h"

#include <gtest/gtest.h>

#include <map>
#include <utility>

namespace hv {
namespace {

using Ring = std::vector<glm::dvec2>;

double triangleArea(const std::vector<glm::dvec2>& pts, const glm::uvec3& t) {
  const glm::dvec2 a = pts[t.x], b = pts[t.y], c = pts[t.z];
  return 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
}

std::vector<glm::dvec2> concat(const std::vector<Ring>& rings) {
  std::vector<glm::dvec2> out;
  for (const Ring& r : rings) out.insert(out.end(), r.begin(), r.end());
  return out;
}

// Every triangle counter-clockwise, the areas summing to the polygon's (shoelace, by hand),
// none of them over a hole (their centroids), n + 2h - 2 triangles (no vertex added).
void expectCovers(const std::vector<Ring>& rings, double area, std::size_t triangles,
                  const std::vector<std::pair<glm::dvec2, glm::dvec2>>& holeBoxes = {}) {
  const std::vector<glm::uvec3> tris = earClipPolygon(rings, "test");
  const std::vector<glm::dvec2> pts = concat(rings);
  double sum = 0.0;
  for (const glm::uvec3& t : tris) {
    const double a = triangleArea(pts, t);
    EXPECT_GT(a, 0.0);
    sum += a;
    const glm::dvec2 c = (pts[t.x] + pts[t.y] + pts[t.z]) / 3.0;
    for (const auto& [lo, hi] : holeBoxes)
      EXPECT_FALSE(c.x > lo.x && c.x < hi.x && c.y > lo.y && c.y < hi.y) << "a triangle over a hole";
  }
  EXPECT_NEAR(sum, area, 1e-9);
  EXPECT_EQ(tris.size(), triangles);
}

TEST(TwiceSignedArea, SignFollowsTheWinding) {
  // A 4 x 3 right triangle (area 6) and a unit square, both ways round.
  EXPECT_DOUBLE_EQ(twiceSignedArea(Ring{{0, 0}, {4, 0}, {0, 3}}), 12.0);
  EXPECT_DOUBLE_EQ(twiceSignedArea(Ring{{0, 0}, {0, 3}, {4, 0}}), -12.0);
  EXPECT_DOUBLE_EQ(twiceSignedArea(Ring{{10, 10}, {11, 10}, {11, 11}, {10, 11}}), 2.0);
  EXPECT_DOUBLE_EQ(twiceSignedArea(Ring{{0, 0}, {1, 0}, {2, 0}}), 0.0);  // collinear
}

TEST(EarClip, ConvexAndConcaveRings) {
  expectCovers({{{0, 0}, {4, 0}, {4, 3}, {0, 3}}}, 12.0, 2);
  // An L (area 4 x 4 - 2 x 2), given clockwise: oriented first.
  expectCovers({{{0, 0}, {0, 4}, {2, 4}, {2, 2}, {4, 2}, {4, 0}}}, 12.0, 4);
  // A comb: reflex corners whose ears are blocked by other vertices.
  expectCovers({{{0, 0}, {5, 0}, {5, 3}, {4, 3}, {4, 1}, {3, 1}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}}},
               15.0 - 4.0, 10);
}

TEST(EarClip, Holes) {
  // A 10 x 10 square with two 2 x 2 holes (clockwise or not: oriented first).
  const std::vector<Ring> rings = {
      {{0, 0}, {10, 0}, {10, 10}, {0, 10}}, {{2, 2}, {4, 2}, {4, 4}, {2, 4}}, {{6, 6}, {6, 8}, {8, 8}, {8, 6}}};
  expectCovers(rings, 100.0 - 8.0, 4 + 4 + 4 + 2 * 2 - 2, {{{2, 2}, {4, 4}}, {{6, 6}, {8, 8}}});
}

TEST(EarClip, Refusals) {
  EXPECT_THROW(earClipPolygon({{{0, 0}, {1, 0}}}, "two points"), InputError);
  EXPECT_THROW(earClipPolygon({{{0, 0}, {1, 0}, {2, 0}}}, "a line"), InputError);
  EXPECT_THROW(earClipPolygon({{{0, 0}, {1, 0}, {NAN, 1}}}, "nan"), InputError);
}

TEST(Lod1EarClip, ClosedPrismWithTheRingsArea) {
  Footprint fp;
  fp.id = "b";
  fp.rings = {{{0, 0}, {0, 4}, {2, 4}, {2, 2}, {4, 2}, {4, 0}, {0, 0}}};  // closed, clockwise
  const Mesh m = extrudeLod1EarClip(fp, 10.0, 15.0);
  EXPECT_EQ(m.positions.size(), 12u);
  // 4 roof + 4 floor + 2 per wall (6 walls).
  EXPECT_EQ(m.triangles.size(), 4u + 4u + 12u);
  // Closed and consistently oriented: each directed edge once, its reverse once.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : m.triangles)
    for (auto e : {std::make_pair(t.x, t.y), std::make_pair(t.y, t.z), std::make_pair(t.z, t.x)}) ++directed[e];
  for (const auto& [e, n] : directed) {
    EXPECT_EQ(n, 1);
    EXPECT_EQ(directed.count({e.second, e.first}), 1u);
  }
  // Volume (divergence theorem) = area x height = 12 x 5.
  double volume = 0.0;
  for (const auto& t : m.triangles)
    volume += glm::dot(m.positions[t.x], glm::cross(m.positions[t.y], m.positions[t.z])) / 6.0;
  EXPECT_NEAR(volume, 60.0, 1e-6);
  EXPECT_THROW(extrudeLod1EarClip(fp, 10.0, 10.0), InputError);
}

TEST(Lod1With, BasesHeightsAndValidity) {
  Heightfield dtm;  // 3 x 3 samples, 1 m cells, z = 5 + column
  dtm.cols = dtm.rows = 3;
  dtm.originX = 0.0;
  dtm.originY = 3.0;
  dtm.z = {5, 6, 7, 5, 6, 7, 5, 6, 7};
  Footprint a, b, c;
  a.id = "a";
  a.rings = {{{1.2, 1.2}, {2.8, 1.2}, {2.8, 1.8}, {1.2, 1.8}}};
  a.height = 3.0;
  a.validFrom = "1900";
  b = a;
  b.id = "b";
  b.height.reset();  // no height: skipped with a warning
  c = a;
  c.id = "c";
  c.base = 100.0;
  c.top = 104.0;
  c.validTo = "not a date";
  Diagnostics diag;
  const Mesh m = buildLod1With({a, b, c}, &dtm, diag, extrudeLod1EarClip);
  double lowA = 1e9, highA = -1e9, lowC = 1e9, highC = -1e9;
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const double z = m.positions[m.triangles[t][k]].z;
      double& lo = m.triangleTags[t] == 0 ? lowA : lowC;
      double& hi = m.triangleTags[t] == 0 ? highA : highC;
      lo = std::min(lo, z), hi = std::max(hi, z);
      EXPECT_NE(m.triangleTags[t], 1u);
    }
  // a's lowest terrain: the vertex x = 1.2 (bilinear: 5 + 1.2 - 0.5), no sample inside it lower.
  EXPECT_NEAR(lowA, 5.7, 1e-6);
  EXPECT_NEAR(highA, 8.7, 1e-6);
  EXPECT_EQ(lowC, 100.0);
  EXPECT_EQ(highC, 104.0);
  ASSERT_EQ(diag.warnings.size(), 1u);
  EXPECT_NE(diag.warnings[0].find("footprint b"), std::string::npos);
  const std::vector<DateInterval> v = footprintValidity({a, b, c}, "from", "to", "f.json", diag);
  ASSERT_EQ(v.size(), 3u);
  EXPECT_EQ(v[0].first, daysFromCivil(1900, 1, 1));
  EXPECT_EQ(v[2].first, daysFromCivil(1900, 1, 1));  // c's validFrom is a's
  EXPECT_EQ(v[2].last, DateInterval{}.last);         // its validTo did not parse: open
  ASSERT_EQ(diag.warnings.size(), 2u);
  EXPECT_NE(diag.warnings[1].find("f.json: footprint c: to: expected an ISO 8601 date"), std::string::npos);
}

}  // namespace
}  // namespace hv
