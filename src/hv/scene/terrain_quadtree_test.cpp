#include "hv/scene/terrain_quadtree.h"

#include "hv/scene/native/raycast.h"

#include <gtest/gtest.h>

#include <iostream>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <set>

namespace hv {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Heightfield makeField(int cols, int rows, double cell, const std::function<double(double, double)>& f) {
  Heightfield h;
  h.cols = cols, h.rows = rows;
  h.originX = 651000.0, h.originY = 6862000.0;
  h.cellX = cell, h.cellY = -cell;
  h.z.resize(size_t(cols) * rows);
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) {
      const glm::dvec2 p = h.samplePosition(i, j);
      h.z[size_t(j) * cols + i] = float(f(p.x, p.y));
    }
  return h;
}

// The height of the mesh's up-facing triangles above (x, y) (a 2D barycentric test, independent
// of the quadtree's own surface evaluation); NaN where none covers it.
double heightAt(const Mesh& mesh, double x, double y) {
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::dvec3 a = mesh.positions[t.x], b = mesh.positions[t.y], c = mesh.positions[t.z];
    const double det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    if (det <= 0.0) continue;  // skirts (vertical: 0) and anything not up-facing
    const double l1 = ((x - a.x) * (c.y - a.y) - (c.x - a.x) * (y - a.y)) / det;
    const double l2 = ((b.x - a.x) * (y - a.y) - (x - a.x) * (b.y - a.y)) / det;
    const double l0 = 1.0 - l1 - l2;
    constexpr double e = -1e-9;
    if (l0 >= e && l1 >= e && l2 >= e) return l0 * a.z + l1 * b.z + l2 * c.z;
  }
  return kNaN;
}

// The extent of a node in full-resolution sample coordinates: [x0, x1] x [y0, y1].
glm::dvec4 nodeExtent(const TerrainQuadtree& q, TerrainNodeId id) {
  const int l = TerrainQuadtree::levelOf(id), s = q.step(l), n = q.tileCells();
  const auto pos = [&](int k, int count) { return double(std::min<std::int64_t>(std::int64_t(k) * s, count - 1)); };
  const int tx = TerrainQuadtree::txOf(id), ty = TerrainQuadtree::tyOf(id);
  return {pos(tx * n, q.grid().cols), pos(std::min(tx * n + n, q.lastSampleX(l)), q.grid().cols),
          pos(ty * n, q.grid().rows), pos(std::min(ty * n + n, q.lastSampleY(l)), q.grid().rows)};
}

TEST(TerrainQuadtree, LevelsAndNodesCoverTheRaster) {
  // 1001 x 600 samples, 64-cell tiles: 1000 cells need 2^4 root cells of 64 -> L = 4.
  auto source =
      std::make_shared<HeightfieldTerrainSource>(makeField(1001, 600, 1.0, [](double, double) { return 5.0; }));
  TerrainQuadtree q(source, {64});
  EXPECT_EQ(q.maxLevel(), 4);
  EXPECT_EQ(q.lastSampleX(4), 1000);
  EXPECT_EQ(q.lastSampleX(0), 63);  // ceil(1000 / 16)
  EXPECT_EQ(q.lastSampleY(0), 38);  // ceil(599 / 16)
  // Every level's tiles cover [0, cols - 1] x [0, rows - 1] exactly once.
  for (int l = 0; l <= q.maxLevel(); ++l) {
    double area = 0.0;
    int count = 0;
    for (int ty = 0; ty < 64; ++ty)
      for (int tx = 0; tx < 64; ++tx) {
        const TerrainNodeId id = TerrainQuadtree::makeId(l, tx, ty);
        if (!q.exists(id)) continue;
        const glm::dvec4 e = nodeExtent(q, id);
        area += (e.y - e.x) * (e.w - e.z);
        ++count;
        if (l > 0) {  // inside its parent
          const glm::dvec4 p = nodeExtent(q, q.parent(id));
          EXPECT_TRUE(e.x >= p.x && e.y <= p.y && e.z >= p.z && e.w <= p.w) << l << " " << tx << " " << ty;
        }
      }
    EXPECT_DOUBLE_EQ(area, 1000.0 * 599.0) << "level " << l;
    EXPECT_GT(count, 0);
  }
  // Level 1 has 125 x 75 cells: two tiles of at most 64 per axis.
  EXPECT_EQ(q.children(TerrainQuadtree::root()).size(), 4u);
  EXPECT_FALSE(q.exists(TerrainQuadtree::makeId(1, 2, 0)));
}

TEST(TerrainQuadtree, LevelSamplesOfAPlaneAreThePlane) {
  // Averaging and bilinear interpolation (with the edge extrapolation) reproduce a plane exactly:
  // every level's samples are the plane at the full-resolution sample they sit on.
  const auto plane = [](double x, double y) { return 0.3 * (x - 651000.0) - 0.2 * (y - 6862000.0) + 40.0; };
  const Heightfield f = makeField(512, 384, 2.0, plane);
  HeightfieldTerrainSource source(f);
  for (int step : {1, 2, 4, 8, 16}) {
    const int nx = (f.cols - 1) / step + 1, ny = (f.rows - 1) / step + 1;
    const std::vector<float> z = source.levelSamples(step, 0, 0, nx, ny);
    for (int b = 0; b < ny; ++b)
      for (int a = 0; a < nx; ++a) {
        const glm::dvec2 p = f.samplePosition(a * step, b * step);
        ASSERT_NEAR(z[size_t(b) * nx + a], plane(p.x, p.y), 1e-3) << "step " << step << " at " << a << "," << b;
      }
  }
}

TEST(TerrainQuadtree, TileHeightsWithinTheLevelsInterpolationError) {
  // A smooth terrain with bounded second derivatives: |f_xx|, |f_yy|, |f_xy| <= M with
  // M = A / lambda^2 (lambda the shorter wavelength / 2 pi), plus a slope (which the bound must not
  // need: a level shifted by half a cell would be off by slope * h / 2).
  const double A = 6.0, lx = 40.0, ly = 55.0;
  const auto f = [&](double x, double y) {
    const double u = x - 651000.0, v = y - 6862000.0;
    return 30.0 + 0.25 * u - 0.15 * v + A * std::sin(u / lx) * std::cos(v / ly);
  };
  const double M = A / (lx * lx);  // the largest of A/lx^2, A/ly^2, A/(lx ly)
  const double cell = 1.0;
  const Heightfield field = makeField(512, 512, cell, f);  // every level's blocks are whole
  auto source = std::make_shared<HeightfieldTerrainSource>(field);
  TerrainQuadtree q(source, {32});
  ASSERT_EQ(q.maxLevel(), 4);
  std::mt19937 rng(7);
  for (int l = 0; l <= q.maxLevel(); ++l) {
    // The bound, for level cells of h = step * cell (derivation in docs/design.md, "Terrain tiles"):
    // an overview sample (a block mean) is within M h^2 / 2 of f at the block's centre; bilinear
    // interpolation or extrapolation (t in [-0.5, 1.5]: weights of absolute sum <= 2) adds
    // 0.75 M h^2 and doubles the samples' error (M h^2 in all); the tile's triangles add M h^2;
    // the full-resolution bilinear reference differs from f by up to M cell^2 / 4.
    const double h = q.step(l) * cell;
    const double bound = 2.75 * M * h * h + 0.25 * M * cell * cell + 1e-3;
    double worst = 0.0;
    for (int trial = 0; trial < 4; ++trial) {
      const int k = 1 << l;
      const TerrainNodeId id = TerrainQuadtree::makeId(l, int(rng() % k), int(rng() % k));
      ASSERT_TRUE(q.exists(id));
      const Mesh m = q.tileMesh(id, false);
      const Aabb b = m.bounds();
      std::uniform_real_distribution<double> ux(b.lo.x, b.hi.x), uy(b.lo.y, b.hi.y);
      for (int s = 0; s < 200; ++s) {
        const double x = ux(rng), y = uy(rng);
        const double z = heightAt(m, x, y);
        const auto ref = field.elevation(x, y);
        ASSERT_FALSE(std::isnan(z));
        ASSERT_TRUE(ref.has_value());
        worst = std::max(worst, std::abs(z - *ref));
      }
    }
    EXPECT_LE(worst, bound) << "level " << l << " (h = " << h << " m)";
    // The bound is not vacuous: a shift of half a level cell along the slope (0.25) would break it
    // from the level where it starts to matter.
    if (l >= 1) EXPECT_LT(bound, 0.25 * h / 2) << "level " << l;
    std::cout << "level " << l << ": worst " << worst << " m, bound " << bound << " m\n";
  }
}

TEST(TerrainQuadtree, GeometricErrorIsTheDeviationFromTheChildrensSamples) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 2.0);
  Heightfield field = makeField(257, 257, 1.0, [&](double, double) { return 0.0; });
  for (float& z : field.z) z = float(noise(rng));
  auto source = std::make_shared<HeightfieldTerrainSource>(field);
  TerrainQuadtree q(source, {32});
  for (TerrainNodeId id :
       {TerrainQuadtree::root(), TerrainQuadtree::makeId(1, 1, 0), TerrainQuadtree::makeId(2, 2, 3)}) {
    const TerrainTile& t = q.tile(id);
    const Mesh m = q.tileMesh(id, false);
    // Independently: the tile mesh's height at every sample of the next level inside it.
    const int l = t.level, s = q.step(l + 1);
    double deviation = 0.0;
    const glm::dvec4 e = nodeExtent(q, id);
    const int k0x = int(e.x) / s, k1x = int(e.y) / s, k0y = int(e.z) / s, k1y = int(e.w) / s;
    const std::vector<float> fine = source->levelSamples(s, k0x, k0y, k1x - k0x + 1, k1y - k0y + 1);
    for (int b = 0; b <= k1y - k0y; ++b)
      for (int a = 0; a <= k1x - k0x; ++a) {
        const glm::dvec2 p = q.grid().position((k0x + a) * s, (k0y + b) * s);
        deviation = std::max(deviation, std::abs(heightAt(m, p.x, p.y) - fine[size_t(b) * (k1x - k0x + 1) + a]));
      }
    EXPECT_NEAR(t.error, deviation, 1e-4) << "level " << l;
    EXPECT_GT(t.error, 0.5);
  }
  // The finest level is the raster: no error.
  EXPECT_EQ(q.tile(TerrainQuadtree::makeId(q.maxLevel(), 0, 0)).error, 0.0);
}

TEST(TerrainQuadtree, SelectionRefinesNearTheCameraAndCoarsensFarAway) {
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  Heightfield field = makeField(1025, 1025, 1.0, [](double x, double) { return 0.01 * (x - 651000.0); });
  for (float& z : field.z) z += float(noise(rng));
  auto source = std::make_shared<HeightfieldTerrainSource>(field);
  TerrainQuadtree q(source, {32});
  ASSERT_EQ(q.maxLevel(), 5);
  // A camera 20 m above the north-west corner, looking south-east.
  const glm::dvec2 nw = field.samplePosition(10, 10), se = field.samplePosition(1014, 1014);
  const Camera cam = lookAtCamera("v", {nw.x, nw.y, 25.0}, {se.x, se.y, 0.0}, 1000, 800, 800.0);
  const std::vector<TerrainNodeId> nodes = q.select(cam, 2.0);
  // They tile the raster exactly once.
  double area = 0.0;
  for (TerrainNodeId id : nodes) {
    const glm::dvec4 e = nodeExtent(q, id);
    area += (e.y - e.x) * (e.w - e.z);
  }
  EXPECT_DOUBLE_EQ(area, 1024.0 * 1024.0);
  auto levelAt = [&](double i, double j) {
    for (TerrainNodeId id : nodes) {
      const glm::dvec4 e = nodeExtent(q, id);
      if (i >= e.x && i < e.y && j >= e.z && j < e.w) return TerrainQuadtree::levelOf(id);
    }
    return -1;
  };
  EXPECT_EQ(levelAt(10, 10), q.maxLevel());
  EXPECT_LE(levelAt(1000, 1000), q.maxLevel() - 3);
  // Every selected node is fine enough from the camera, and each one's parent was not.
  for (TerrainNodeId id : nodes) {
    if (TerrainQuadtree::levelOf(id) < q.maxLevel()) EXPECT_LE(q.screenSpaceError(id, cam), 2.0);
    if (TerrainQuadtree::levelOf(id) > 0) EXPECT_GT(q.screenSpaceError(q.parent(id), cam), 2.0);
  }

  // A second viewpoint at the far corner: the selection for both refines both corners.
  const Camera far = lookAtCamera("w", {se.x, se.y, 25.0}, {nw.x, nw.y, 0.0}, 1000, 800, 800.0);
  const TerrainSelection both = q.select({cam, far}, 2.0, std::numeric_limits<std::size_t>::max());
  std::set<TerrainNodeId> set(both.nodes.begin(), both.nodes.end());
  auto levelIn = [&](const std::vector<TerrainNodeId>& list, double i, double j) {
    for (TerrainNodeId id : list) {
      const glm::dvec4 e = nodeExtent(q, id);
      if (i >= e.x && i < e.y && j >= e.z && j < e.w) return TerrainQuadtree::levelOf(id);
    }
    return -1;
  };
  EXPECT_EQ(levelIn(both.nodes, 10, 10), q.maxLevel());
  EXPECT_EQ(levelIn(both.nodes, 1014, 1014), q.maxLevel());
  EXPECT_FALSE(both.budgetLimited);

  // A budget: fewer triangles, the far corner coarser first (the cameras' neighbourhoods keep the
  // finest level, the middle of the raster, far from both, is what coarsens).
  const std::size_t budget = both.triangles / 3;
  const TerrainSelection limited = q.select({cam, far}, 2.0, budget);
  EXPECT_TRUE(limited.budgetLimited);
  EXPECT_LE(limited.triangles, budget);
  EXPECT_EQ(levelIn(limited.nodes, 10, 10), q.maxLevel());
  EXPECT_LE(levelIn(limited.nodes, 512, 512), levelIn(both.nodes, 512, 512));
  EXPECT_LT(limited.nodes.size(), both.nodes.size());
  // The meshes' triangles agree with the estimate within the skirts on the raster's edge.
  const Mesh m = q.mesh(limited.nodes);
  EXPECT_LE(m.triangles.size(), limited.triangles);
  EXPECT_GT(m.triangles.size(), limited.triangles * 9 / 10);
}

// Rays through the borders between tiles of different levels: with skirts, the first hit is no
// farther than the seam (the surface or a skirt stops every ray there); without, some rays pass
// through the cracks.
TEST(TerrainQuadtree, NoCracksBetweenLevels) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.5);
  Heightfield field = makeField(1025, 769, 1.0, [](double, double) { return 100.0; });
  for (float& z : field.z) z += float(noise(rng));
  auto source = std::make_shared<HeightfieldTerrainSource>(field);
  TerrainQuadtree q(source, {16});
  const glm::dvec2 nw = field.samplePosition(20, 20), se = field.samplePosition(1000, 760);
  const Camera cam = lookAtCamera("v", {nw.x, nw.y, 120.0}, {se.x, se.y, 100.0}, 1000, 800, 800.0);
  const std::vector<TerrainNodeId> nodes = q.select(cam, 2.0);
  std::set<int> levels;
  for (TerrainNodeId id : nodes) levels.insert(TerrainQuadtree::levelOf(id));
  ASSERT_GE(levels.size(), 3u);

  // Seams between nodes of different levels: points on a vertical border shared by two nodes.
  struct Seam {
    glm::dvec2 xy;
    TerrainNodeId a, b;
  };
  std::vector<Seam> seams;
  for (TerrainNodeId ia : nodes)
    for (TerrainNodeId ib : nodes) {
      if (TerrainQuadtree::levelOf(ia) >= TerrainQuadtree::levelOf(ib)) continue;
      const glm::dvec4 ea = nodeExtent(q, ia), eb = nodeExtent(q, ib);
      // a's east or west border on b's, over a common stretch of rows.
      for (double x : {ea.x, ea.y}) {
        if (x != eb.x && x != eb.y) continue;
        const double lo = std::max(ea.z, eb.z), hi = std::min(ea.w, eb.w);
        for (double j = lo + 0.37; j < hi; j += 1.3) seams.push_back({q.grid().position(x, j), ia, ib});
      }
    }
  ASSERT_GT(seams.size(), 100u);

  for (bool skirts : {true, false}) {
    const Mesh mesh = q.mesh(nodes, skirts);
    const RayCaster caster(mesh);
    int escaped = 0, tested = 0;
    for (const Seam& s : seams) {
      const double za = heightAt(q.tileMesh(s.a, false), s.xy.x, s.xy.y);
      const double zb = heightAt(q.tileMesh(s.b, false), s.xy.x, s.xy.y);
      if (std::isnan(za) || std::isnan(zb) || std::abs(za - zb) < 0.05) continue;
      const glm::dvec3 p(s.xy, 0.5 * (za + zb));  // in the gap between the two levels' surfaces
      for (double side : {-1.0, 1.0}) {
        const glm::dvec3 dir = glm::normalize(glm::dvec3(side, 0.2, -0.6));
        const glm::dvec3 origin = p - 50.0 * dir;
        const auto hit = caster.intersect(origin, dir);
        ++tested;
        if (!hit || hit->t > 50.0 + 1e-3) ++escaped;
      }
      // A vertical ray through the seam meets the surface.
      EXPECT_TRUE(caster.intersect({s.xy, 1000.0}, {0.0, 0.0, -1.0}).has_value());
    }
    ASSERT_GT(tested, 50);
    std::cout << (skirts ? "with" : "without") << " skirts: " << escaped << " of " << tested << " rays through the seams\n";
    if (skirts)
      EXPECT_EQ(escaped, 0) << "of " << tested;
    else
      EXPECT_GT(escaped, tested / 10) << "the rays do reach the cracks: without skirts some pass";
  }
}

TEST(TerrainQuadtree, TileMeshIsUpFacingAndSkirtsFaceOutwards) {
  const Heightfield field =
      makeField(129, 129, 1.0, [](double x, double y) { return 0.1 * (x - 651000.0) + 0.05 * (y - 6862000.0); });
  TerrainQuadtree q(std::make_shared<HeightfieldTerrainSource>(field), {32});
  const TerrainNodeId id = TerrainQuadtree::makeId(2, 1, 1);  // an inner tile: four shared borders
  const Mesh m = q.tileMesh(id, true);
  const Mesh bare = q.tileMesh(id, false);
  EXPECT_EQ(bare.triangles.size(), 2u * 32 * 32);
  EXPECT_EQ(m.triangles.size(), bare.triangles.size() + 4u * 2 * 32);
  const glm::dvec3 centre = bare.bounds().center();
  for (size_t k = 0; k < m.triangles.size(); ++k) {
    const glm::uvec3 t = m.triangles[k];
    const glm::dvec3 n = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
    if (k < bare.triangles.size()) {
      ASSERT_GT(n.z, 0.0) << k;
    } else {
      ASSERT_NEAR(n.z, 0.0, 1e-6) << k;  // vertical
      const glm::dvec3 mid = (m.positions[t.x] + m.positions[t.y] + m.positions[t.z]) / 3.0;
      ASSERT_GT(glm::dot(glm::dvec2(n), glm::dvec2(mid - centre)), 0.0) << k;
    }
  }
  // The corner tile has no skirt on the raster's edge.
  EXPECT_EQ(q.tileMesh(TerrainQuadtree::makeId(2, 0, 0), true).triangles.size(), 2u * 32 * 32 + 2u * 2 * 32);
}

TEST(TerrainQuadtree, LevelHeightfieldSitsOnTheLevelsSamples) {
  const auto plane = [](double x, double y) { return 0.5 * (x - 651000.0) + 0.25 * (y - 6862000.0); };
  const Heightfield field = makeField(300, 200, 2.0, plane);
  TerrainQuadtree q(std::make_shared<HeightfieldTerrainSource>(field), {32});
  const Heightfield h = q.levelHeightfield(q.maxLevel() - 2);  // step 4
  EXPECT_EQ(h.cols, 75);                                       // samples 0, 4, ..., 296
  EXPECT_EQ(h.rows, 50);
  for (int j : {0, 17, 49})
    for (int i : {0, 33, 74}) {
      EXPECT_EQ(h.samplePosition(i, j), field.samplePosition(4 * i, 4 * j));
      const glm::dvec2 p = h.samplePosition(i, j);
      EXPECT_NEAR(h.at(i, j), plane(p.x, p.y), 1e-3);
    }
}

}  // namespace
}  // namespace hv
