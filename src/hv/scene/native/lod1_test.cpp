#include "hv/scene/native/lod1.h"

#include <gtest/gtest.h>

#include <map>
#include <utility>

namespace hv {
namespace {

using Ring = std::vector<glm::dvec2>;

Footprint footprint(std::string id, std::vector<Ring> rings) {
  Footprint fp;
  fp.id = std::move(id);
  fp.rings = std::move(rings);
  return fp;
}

glm::dvec3 faceNormal(const Mesh& m, size_t t) {
  const glm::uvec3& tri = m.triangles[t];
  return glm::cross(m.positions[tri.y] - m.positions[tri.x], m.positions[tri.z] - m.positions[tri.x]);
}

// Closed and consistently oriented: each directed edge appears once and its reverse once.
void expectClosed(const Mesh& m) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : m.triangles) {
    ++directed[{t.x, t.y}];
    ++directed[{t.y, t.z}];
    ++directed[{t.z, t.x}];
  }
  for (const auto& [edge, n] : directed) {
    EXPECT_EQ(n, 1) << "edge " << edge.first << "->" << edge.second << " used " << n << " times";
    const auto back = directed.find({edge.second, edge.first});
    EXPECT_TRUE(back != directed.end() && back->second == 1)
        << "edge " << edge.first << "->" << edge.second << " has no single opposite";
  }
}

// Area of the up-facing (roof) or down-facing (floor) triangles.
double horizontalArea(const Mesh& m, bool up) {
  double a = 0.0;
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const glm::dvec3 n = faceNormal(m, t);
    if (up ? n.z > 0.0 : n.z < 0.0) a += 0.5 * glm::length(n);
  }
  return a;
}

// The tolerance asked for: 1e-9 relative (the geometry is exact in double up to rounding).
void expectRelNear(double actual, double expected) {
  EXPECT_NEAR(actual, expected, 1e-9 * std::abs(expected));
}

void expectPrism(const Mesh& m, double footprintArea, double baseZ, double topZ) {
  expectClosed(m);
  expectRelNear(m.signedVolume(), footprintArea * (topZ - baseZ));
  expectRelNear(horizontalArea(m, true), footprintArea);
  expectRelNear(horizontalArea(m, false), footprintArea);
  EXPECT_DOUBLE_EQ(m.bounds().lo.z, baseZ);
  EXPECT_DOUBLE_EQ(m.bounds().hi.z, topZ);
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const glm::dvec3 n = faceNormal(m, t);
    EXPECT_GT(glm::length(n), 0.0) << "degenerate triangle " << t;
    // Every triangle is either horizontal (roof/floor) or vertical (wall).
    EXPECT_TRUE((n.x == 0.0 && n.y == 0.0) || n.z == 0.0) << "triangle " << t;
  }
}

TEST(Lod1, Square) {
  const Mesh m = extrudeLod1(footprint("sq", {{{0, 0}, {10, 0}, {10, 10}, {0, 10}}}), 35.0, 47.0);
  expectPrism(m, 100.0, 35.0, 47.0);
  EXPECT_EQ(m.triangles.size(), 2u + 2u + 4u * 2u);
  EXPECT_TRUE(m.triangleTags.empty());
  // Walls face away from the centre (5, 5).
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const glm::dvec3 n = faceNormal(m, t);
    if (n.z != 0.0) continue;
    const glm::dvec3 c =
        (m.positions[m.triangles[t].x] + m.positions[m.triangles[t].y] + m.positions[m.triangles[t].z]) / 3.0;
    EXPECT_GT(glm::dot(glm::dvec2(n), glm::dvec2(c) - glm::dvec2(5.0, 5.0)), 0.0);
  }
}

TEST(Lod1, ConcaveLShapeGivenClockwise) {
  // Clockwise on purpose: 6 x 2 + 2 x 3 = 18 m^2.
  Ring l = {{0, 0}, {6, 0}, {6, 2}, {2, 2}, {2, 5}, {0, 5}};
  std::reverse(l.begin(), l.end());
  expectPrism(extrudeLod1(footprint("L", {l}), 0.0, 4.0), 18.0, 0.0, 4.0);
}

TEST(Lod1, ConcaveUShapeWithCollinearVertexAndClosingPoint) {
  // 9 x 6 - 3 x 4 = 42 m^2; (4.5, 0) lies on the bottom edge, and the ring repeats its first point.
  const Ring u = {{0, 0}, {4.5, 0}, {9, 0}, {9, 6}, {6, 6}, {6, 2}, {3, 2}, {3, 6}, {0, 6}, {0, 0}};
  const Mesh m = extrudeLod1(footprint("U", {u}), 100.0, 109.5);
  expectPrism(m, 42.0, 100.0, 109.5);
  EXPECT_EQ(m.positions.size(), 2u * 9u);  // closing repeat dropped
  // 9 vertices: 7 roof triangles, 7 floor triangles, 9 wall quads.
  EXPECT_EQ(m.triangles.size(), 7u + 7u + 18u);
}

TEST(Lod1, CourtyardHole) {
  // Outer 20 x 20, hole 10 x 10 (given counter-clockwise, like the shell): 400 - 100 = 300 m^2.
  const Ring outer = {{0, 0}, {20, 0}, {20, 20}, {0, 20}};
  const Ring hole = {{5, 5}, {15, 5}, {15, 15}, {5, 15}};
  const Mesh m = extrudeLod1(footprint("court", {outer, hole}), 10.0, 22.0);
  expectPrism(m, 300.0, 10.0, 22.0);
  // Courtyard walls face into the courtyard (towards its centre), outer walls away from it.
  int inward = 0;
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const glm::dvec3 n = faceNormal(m, t);
    if (n.z != 0.0) continue;
    const glm::dvec3 c =
        (m.positions[m.triangles[t].x] + m.positions[m.triangles[t].y] + m.positions[m.triangles[t].z]) / 3.0;
    const glm::dvec2 fromCentre = glm::dvec2(c) - glm::dvec2(10.0, 10.0);
    const bool courtyardWall = std::abs(fromCentre.x) < 5.0 + 1e-9 && std::abs(fromCentre.y) < 5.0 + 1e-9;
    if (courtyardWall) {
      EXPECT_LT(glm::dot(glm::dvec2(n), fromCentre), 0.0);
      ++inward;
    } else {
      EXPECT_GT(glm::dot(glm::dvec2(n), fromCentre), 0.0);
    }
  }
  EXPECT_EQ(inward, 8);
}

TEST(Lod1, InvalidFootprintsThrowNamingTheId) {
  auto expectThrowWithId = [](const Footprint& fp, double base, double top) {
    try {
      extrudeLod1(fp, base, top);
      ADD_FAILURE() << "no exception for " << fp.id;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fp.id), std::string::npos) << e.what();
    }
  };
  expectThrowWithId(footprint("bowtie-7", {{{0, 0}, {2, 2}, {2, 0}, {0, 2}}}), 0.0, 5.0);
  expectThrowWithId(footprint("two-points-8", {{{0, 0}, {3, 1}}}), 0.0, 5.0);
  expectThrowWithId(footprint("repeats-9", {{{0, 0}, {3, 1}, {3, 1}, {0, 0}}}), 0.0, 5.0);
  expectThrowWithId(footprint("flat-10", {{{0, 0}, {1, 1}, {2, 2}}}), 0.0, 5.0);  // zero area
  expectThrowWithId(
      footprint("hole-outside-11", {{{0, 0}, {4, 0}, {4, 4}, {0, 4}}, {{10, 10}, {11, 10}, {11, 11}}}), 0.0,
      5.0);
  expectThrowWithId(footprint("no-rings-12", {}), 0.0, 5.0);
  const Footprint square = footprint("inverted-13", {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}});
  expectThrowWithId(square, 5.0, 5.0);
  expectThrowWithId(square, 6.0, 5.0);
}

TEST(Lod1, BowTieReasonComesFromGeos) {
  try {
    extrudeLod1(footprint("bowtie", {{{0, 0}, {2, 2}, {2, 0}, {0, 2}}}), 0.0, 5.0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("Self-intersection"), std::string::npos) << e.what();
  }
}

TEST(Lod1, BuildLayerWithTerrainBasesTagsAndWarnings) {
  // Terrain at 7 m: a 4 x 4 grid of 10 m cells over [0, 40] x [0, 40].
  Heightfield terrain;
  terrain.cols = terrain.rows = 4;
  terrain.originX = 0.0;
  terrain.originY = 40.0;
  terrain.cellX = 10.0;
  terrain.cellY = -10.0;
  terrain.z.assign(16, 7.0f);

  std::vector<Footprint> fps;
  fps.push_back(footprint("a", {{{1, 1}, {5, 1}, {5, 5}, {1, 5}}}));  // on the terrain, 16 m^2
  fps[0].height = 10.0;
  fps.push_back(footprint("b", {{{20, 20}, {23, 20}, {23, 22}, {20, 22}}}));  // explicit base and top, 6 m^2
  fps[1].base = 100.0;
  fps[1].top = 104.0;
  fps.push_back(footprint("no-height", {{{30, 30}, {31, 30}, {31, 31}}}));
  fps.push_back(footprint("bowtie", {{{0, 0}, {2, 2}, {2, 0}, {0, 2}}}));
  fps[3].height = 3.0;
  fps.push_back(footprint("c", {{{10, 30}, {12, 30}, {12, 32}, {10, 32}}}));  // 4 m^2, base 7 + 2.5
  fps[4].height = 2.5;

  Diagnostics diag;
  const Mesh m = buildLod1(fps, &terrain, diag);
  ASSERT_EQ(m.triangleTags.size(), m.triangles.size());
  expectClosed(m);
  expectRelNear(m.signedVolume(), 16.0 * 10.0 + 6.0 * 4.0 + 4.0 * 2.5);
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const std::uint32_t tag = m.triangleTags[t];
    EXPECT_TRUE(tag == 0 || tag == 1 || tag == 4) << tag;
    const double z = m.positions[m.triangles[t].x].z;
    const double lo = tag == 0 ? 7.0 : tag == 1 ? 100.0 : 7.0;
    const double hi = tag == 0 ? 17.0 : tag == 1 ? 104.0 : 9.5;
    EXPECT_TRUE(z == lo || z == hi) << "tag " << tag << " z " << z;
  }
  ASSERT_EQ(diag.warnings.size(), 2u);
  EXPECT_NE(diag.warnings[0].find("no-height"), std::string::npos) << diag.warnings[0];
  EXPECT_NE(diag.warnings[1].find("bowtie"), std::string::npos) << diag.warnings[1];
}

TEST(Lod1, BuildWithoutTerrainWarnsAndUsesZero) {
  // A MultiPolygon's parts arrive as separate footprints; two disjoint squares stay two closed prisms.
  std::vector<Footprint> fps = {footprint("m.0", {{{0, 0}, {2, 0}, {2, 2}, {0, 2}}}),
                                footprint("m.1", {{{5, 0}, {8, 0}, {8, 3}, {5, 3}}})};
  fps[0].height = fps[1].height = 6.0;
  Diagnostics diag;
  const Mesh m = buildLod1(fps, nullptr, diag);
  expectClosed(m);
  expectRelNear(m.signedVolume(), (4.0 + 9.0) * 6.0);
  EXPECT_DOUBLE_EQ(m.bounds().lo.z, 0.0);
  ASSERT_EQ(diag.warnings.size(), 2u);
  EXPECT_NE(diag.warnings[0].find("m.0"), std::string::npos);
  EXPECT_NE(diag.warnings[1].find("m.1"), std::string::npos);
}

}  // namespace
}  // namespace hv

namespace hv {
namespace {

// The browser's extrusion (hv/scene/footprint.h: ear clipping for the roof) and the native one
// (GEOS's constrained Delaunay roof) of the same footprint with a hole: the same vertices in the
// same order, the same walls, roofs of the same area.
TEST(Lod1, EarClipExtrusionMatchesGeos) {
  Footprint fp;
  fp.id = "h";
  fp.rings = {{{0, 0}, {10, 0}, {10, 6}, {6, 6}, {6, 10}, {0, 10}}, {{2, 2}, {4, 2}, {4, 4}, {2, 4}}};
  const Mesh geos = extrudeLod1(fp, 1.0, 9.0), ear = extrudeLod1EarClip(fp, 1.0, 9.0);
  EXPECT_EQ(geos.positions, ear.positions);
  ASSERT_EQ(geos.triangles.size(), ear.triangles.size());
  auto roofArea = [](const Mesh& m) {
    double a = 0.0;
    for (const auto& t : m.triangles) {
      const glm::dvec3 n = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
      if (n.z > 0.0 && m.positions[t.x].z == 9.0) a += 0.5 * n.z;
    }
    return a;
  };
  EXPECT_NEAR(roofArea(geos), 100.0 - 16.0 - 4.0, 1e-9);
  EXPECT_NEAR(roofArea(ear), roofArea(geos), 1e-9);
  // The walls: the last 2 x (6 + 4) triangles, the same in both.
  const std::size_t walls = 2 * 10;
  EXPECT_TRUE(std::equal(geos.triangles.end() - walls, geos.triangles.end(), ear.triangles.end() - walls));
}

}  // namespace
}  // namespace hv
