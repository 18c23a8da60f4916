// The demo city's world model: terrain, streets, buildings (LOD1 footprints and the richer ground
// truth), trees and parked cars. See demo_city.h for what and docs/demo-city.md for why.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>

#include "hv/demo/demo_internal.h"
#include "hv/demo/footprint_shapes.h"

namespace hv::demo {

using detail::addBox;
using detail::addQuad;
using detail::addSurface;
using detail::CellSet;
using detail::cellsOf;
using detail::insideRings;
using detail::Rng;
using detail::Shape;
using detail::signedArea;
using detail::traceRings;

const char* materialName(Material m) {
  static constexpr std::array<const char*, size_t(Material::Count)> names = {
      "grass",      "asphalt",    "paving",     "kerb",     "plaster",   "brick",
      "stone",      "glass",      "reveal",     "door",     "balcony",   "roof-gravel",
      "roof-tiles", "tree-trunk", "tree-crown", "car-body", "car-glass", "car-wheel"};
  return size_t(m) < names.size() ? names[size_t(m)] : "unknown";
}

std::uint8_t asprsClass(Material m) {
  switch (m) {
    case Material::Grass:
    case Material::Asphalt:
    case Material::Paving:
    case Material::Kerb:
      return 2;
    case Material::TreeTrunk:
    case Material::TreeCrown:
      return 5;
    case Material::CarBody:
    case Material::CarGlass:
    case Material::CarWheel:
      return 1;
    default:
      return 6;
  }
}

namespace detail {

std::vector<Lot> blockLots(const CitySettings& s, glm::dvec2 b0, double blockW, double blockD, Rng& rng) {
  std::vector<double> cuts{0.0};
  for (int k = 1; k < s.lotsPerRow; ++k) cuts.push_back(k * s.lotWidth + rng.uniform(-0.15, 0.15) * s.lotWidth);
  cuts.push_back(blockW);
  std::vector<Lot> lots;
  for (int row = 0; row < 2; ++row)
    for (int k = 0; k < s.lotsPerRow; ++k) {
      Lot lot;
      lot.origin = b0 + glm::dvec2(cuts[size_t(k)], row == 0 ? 0.0 : blockD);
      lot.u = {1.0, 0.0};
      lot.v = {0.0, row == 0 ? 1.0 : -1.0};
      lot.width = cuts[size_t(k) + 1] - cuts[size_t(k)];
      lot.depth = s.lotDepth;
      lot.gapLeft = k > 0;
      lot.gapRight = k + 1 < s.lotsPerRow;
      lots.push_back(lot);
    }
  return lots;
}

DrawnFootprint drawFootprint(const CitySettings& s, const Lot& lot, bool courtyard, Rng& rng) {
  const double u0 = lot.gapLeft ? s.buildingGap : 0.0, u1 = lot.width - (lot.gapRight ? s.buildingGap : 0.0);
  const double v1 = lot.depth - s.buildingGap;
  const double W = u1 - u0;
  DrawnFootprint out;
  out.shape = courtyard ? Shape::Courtyard : Shape(rng.integer(0, int(Shape::Count) - 2));
  if (out.shape == Shape::Courtyard) {
    out.us = {u0, u0 + 0.3 * W, u0 + 0.7 * W, u1};
    out.vs = {0.0, 0.33 * v1, 0.7 * v1, v1};
  } else {
    out.us = {u0, u0 + rng.uniform(0.28, 0.4) * W, u0 + rng.uniform(0.6, 0.72) * W, u1};
    out.vs = {0.0, rng.uniform(0.38, 0.5) * v1, rng.uniform(0.62, 0.75) * v1, v1};
  }
  out.cells = cellsOf(out.shape);
  for (const auto& ring : traceRings(out.cells)) {
    std::vector<glm::dvec2> r;
    for (glm::ivec2 gv : ring) r.push_back(lot.origin + out.us[size_t(gv.x)] * lot.u + out.vs[size_t(gv.y)] * lot.v);
    out.rings.push_back(r);
  }
  // World orientation: outer ring counter-clockwise, holes clockwise (GeoJSON RFC 7946 §3.1.6);
  // the lot frame of a north row is mirrored, so orient by area, outer (largest) first.
  std::sort(out.rings.begin(), out.rings.end(),
            [](const auto& a, const auto& b) { return std::abs(signedArea(a)) > std::abs(signedArea(b)); });
  for (size_t k = 0; k < out.rings.size(); ++k) {
    const bool ccw = signedArea(out.rings[k]) > 0.0;
    if (ccw != (k == 0)) std::reverse(out.rings[k].begin(), out.rings[k].end());
  }
  out.height = std::round(rng.uniform(s.minHeight, s.maxHeight) * 10.0) / 10.0;
  return out;
}

namespace {
std::uint64_t largeSalt(std::uint32_t seed) { return 0x1a26ec17ULL ^ (std::uint64_t(seed) << 32); }
}  // namespace

Rng blockRng(std::uint32_t seed, int i, int j) { return Rng(hash(i, j, -1, largeSalt(seed))); }

LotDraw lotDraw(const CitySettings& s, std::uint32_t seed, int i, int j, int lot) {
  LotDraw d;
  d.rng = Rng(hash(i, j, lot, largeSalt(seed)));
  d.built = d.rng.chance(s.lotFill);
  d.courtyard = d.rng.chance(s.courtyardShare);
  return d;
}

std::string largeBuildingId(int i, int j, int lot) {
  return "b" + std::to_string(i) + "_" + std::to_string(j) + "_" + std::to_string(lot);
}

}  // namespace detail

glm::dvec2 BlockGrid::blockCorner(int i, int j) const {
  return origin + glm::dvec2(i * pitchX - 0.5 * blockW, j * pitchY - 0.5 * blockD);
}
double BlockGrid::streetX(int i) const { return origin.x + i * pitchX - 0.5 * (blockW + streetWidth); }
double BlockGrid::streetY(int j) const { return origin.y + j * pitchY - 0.5 * (blockD + streetWidth); }
glm::dvec2 BlockGrid::lo() const { return {streetX(i0) - 0.5 * streetWidth, streetY(j0) - 0.5 * streetWidth}; }
glm::dvec2 BlockGrid::hi() const {
  return {streetX(i0 + nbx) + 0.5 * streetWidth, streetY(j0 + nby) + 0.5 * streetWidth};
}

BlockGrid blockGrid(const CitySettings& s, int blocks) {
  BlockGrid g;
  g.streetWidth = 2.0 * s.sidewalkWidth + s.roadWidth;
  g.blockW = s.lotsPerRow * s.lotWidth;
  g.blockD = 2.0 * s.lotDepth;
  g.pitchX = g.blockW + g.streetWidth;
  g.pitchY = g.blockD + g.streetWidth;
  g.origin = s.originXY;
  const int n = std::max(1, blocks);
  // Roughly square in metres: nbx / nby = pitchY / pitchX.
  g.nbx = std::max(1, int(std::lround(std::sqrt(double(n) * g.pitchY / g.pitchX))));
  g.nby = std::max(1, int(std::lround(double(n) / g.nbx)));
  g.i0 = -(g.nbx / 2);
  g.j0 = -(g.nby / 2);
  return g;
}

void forEachFootprint(const DemoOptions& o, const std::function<void(const Footprint&)>& visit,
                      const std::function<void(int done, int rows)>& rowDone) {
  const CitySettings& s = o.city;
  const BlockGrid g = blockGrid(s, o.blocks);
  for (int r = 0; r < g.nby; ++r) {
    const int j = g.j0 + r;
    for (int i = g.i0; i < g.i0 + g.nbx; ++i) {
      Rng block = detail::blockRng(o.seed, i, j);
      const std::vector<detail::Lot> lots = detail::blockLots(s, g.blockCorner(i, j), g.blockW, g.blockD, block);
      for (size_t k = 0; k < lots.size(); ++k) {
        detail::LotDraw d = detail::lotDraw(s, o.seed, i, j, int(k));
        if (!d.built) continue;
        const detail::DrawnFootprint drawn = detail::drawFootprint(s, lots[k], d.courtyard, d.rng);
        Footprint fp;
        fp.id = detail::largeBuildingId(i, j, int(k));
        fp.rings = drawn.rings;
        fp.height = drawn.height;
        visit(fp);
      }
    }
    if (rowDone) rowDone(r + 1, g.nby);
  }
}

namespace {

struct Grid {
  double streetWidth = 0.0, blockW = 0.0, blockD = 0.0;
  int nbx = 0, nby = 0;
  glm::dvec2 lo{0.0}, hi{0.0};  // the street grid, world
};

struct Opening {
  double u0, u1, w0, w1;
  bool door;
};

class CityBuilder {
 public:
  explicit CityBuilder(const DemoOptions& o)
      : o_(o), s_(o.city), rng_(0x5eed0000ULL ^ std::uint64_t(o.seed) * 0x9e37ULL) {}

  World build() {
    w_.options = o_;
    w_.origin = glm::dvec3(s_.originXY, 0.0);
    const double az = glm::radians(s_.sunAzimuthDeg), el = glm::radians(s_.sunElevationDeg);
    w_.sunDirection = glm::dvec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    // Terrain phases: part of the seed's world, drawn before anything else.
    for (double& p : phase_) p = rng_.uniform(0.0, 6.283185307179586);
    w_.phase = phase_;
    if (o_.blocks > 0) {
      layoutLarge();
      makeLargeDtm();
      makeGround();
      makeLargeBuildings();
    } else {
      layout();
      makeDtm();
      makeGround();
      makeBuildings();
    }
    makeTrees();
    makeParkedCars();
    return std::move(w_);
  }

 private:
  const DemoOptions& o_;
  const CitySettings& s_;
  Rng rng_;
  World w_;
  Grid g_;
  std::array<double, 3> phase_{};
  glm::dvec2 domainLo_{0.0}, domainHi_{0.0};
  std::vector<Aabb> balconyBoxes_;
  BlockGrid grid_;                               // large city: the lattice
  int ti0_ = 0, ti1_ = -1, tj0_ = 0, tj1_ = -1;  // large city: the ground-truth blocks

  void layout() {
    const int n = std::max(1, o_.buildings);
    const int lotsPerBlock = 2 * s_.lotsPerRow;
    const int blocks = (n + lotsPerBlock - 1) / lotsPerBlock;
    g_.nbx = int(std::ceil(std::sqrt(double(blocks))));
    g_.nby = (blocks + g_.nbx - 1) / g_.nbx;
    g_.streetWidth = 2.0 * s_.sidewalkWidth + s_.roadWidth;
    g_.blockW = s_.lotsPerRow * s_.lotWidth;
    g_.blockD = 2.0 * s_.lotDepth;
    const glm::dvec2 total(g_.nbx * g_.blockW + (g_.nbx + 1) * g_.streetWidth,
                           g_.nby * g_.blockD + (g_.nby + 1) * g_.streetWidth);
    g_.lo = s_.originXY - 0.5 * total;
    g_.hi = s_.originXY + 0.5 * total;
    domainLo_ = g_.lo - glm::dvec2(s_.margin);
    domainHi_ = g_.hi + glm::dvec2(s_.margin);
    const double pitchX = g_.blockW + g_.streetWidth, pitchY = g_.blockD + g_.streetWidth;
    for (int i = 0; i <= g_.nbx; ++i)
      w_.streets.push_back({false, g_.lo.x + 0.5 * g_.streetWidth + i * pitchX, g_.lo.y, g_.hi.y});
    for (int j = 0; j <= g_.nby; ++j)
      w_.streets.push_back({true, g_.lo.y + 0.5 * g_.streetWidth + j * pitchY, g_.lo.x, g_.hi.x});
    w_.streetWidth = g_.streetWidth;
    w_.roadWidth = s_.roadWidth;
    w_.kerbHeight = s_.kerbHeight;
    w_.cityBounds.extend(glm::dvec3(g_.lo, 0.0));
    w_.cityBounds.extend(glm::dvec3(g_.hi, 0.0));
    w_.surveyStreets = w_.streets;
  }

  // A large city: the blocks within truthRadius of the centre block get the ground truth; the
  // streets of those within surveyRadius carry the cameras and the lidar.
  void layoutLarge() {
    const BlockGrid bg = blockGrid(s_, o_.blocks);
    g_.streetWidth = bg.streetWidth;
    g_.blockW = bg.blockW;
    g_.blockD = bg.blockD;
    const int ti0 = std::max(bg.i0, -s_.truthRadius), ti1 = std::min(bg.i0 + bg.nbx - 1, s_.truthRadius);
    const int tj0 = std::max(bg.j0, -s_.truthRadius), tj1 = std::min(bg.j0 + bg.nby - 1, s_.truthRadius);
    ti0_ = ti0, ti1_ = ti1, tj0_ = tj0, tj1_ = tj1;
    g_.nbx = ti1 - ti0 + 1;
    g_.nby = tj1 - tj0 + 1;
    const double hw = 0.5 * bg.streetWidth;
    g_.lo = {bg.streetX(ti0) - hw, bg.streetY(tj0) - hw};
    g_.hi = {bg.streetX(ti1 + 1) + hw, bg.streetY(tj1 + 1) + hw};
    // Grass beyond the city's own edge; where the zone ends inside the city, the next blocks begin.
    const glm::dvec2 cityLo = bg.lo(), cityHi = bg.hi();
    domainLo_ = g_.lo - glm::dvec2(g_.lo.x <= cityLo.x ? s_.margin : 0.0, g_.lo.y <= cityLo.y ? s_.margin : 0.0);
    domainHi_ = g_.hi + glm::dvec2(g_.hi.x >= cityHi.x ? s_.margin : 0.0, g_.hi.y >= cityHi.y ? s_.margin : 0.0);
    for (int i = ti0; i <= ti1 + 1; ++i) w_.streets.push_back({false, bg.streetX(i), g_.lo.y, g_.hi.y});
    for (int j = tj0; j <= tj1 + 1; ++j) w_.streets.push_back({true, bg.streetY(j), g_.lo.x, g_.hi.x});
    const int si0 = std::max(bg.i0, -s_.surveyRadius), si1 = std::min(bg.i0 + bg.nbx - 1, s_.surveyRadius);
    const int sj0 = std::max(bg.j0, -s_.surveyRadius), sj1 = std::min(bg.j0 + bg.nby - 1, s_.surveyRadius);
    const glm::dvec2 sLo(bg.streetX(si0) - hw, bg.streetY(sj0) - hw);
    const glm::dvec2 sHi(bg.streetX(si1 + 1) + hw, bg.streetY(sj1 + 1) + hw);
    for (int i = si0; i <= si1 + 1; ++i) w_.surveyStreets.push_back({false, bg.streetX(i), sLo.y, sHi.y});
    for (int j = sj0; j <= sj1 + 1; ++j) w_.surveyStreets.push_back({true, bg.streetY(j), sLo.x, sHi.x});
    w_.streetWidth = g_.streetWidth;
    w_.roadWidth = s_.roadWidth;
    w_.kerbHeight = s_.kerbHeight;
    w_.cityBounds.extend(glm::dvec3(g_.lo, 0.0));
    w_.cityBounds.extend(glm::dvec3(g_.hi, 0.0));
    grid_ = bg;
  }

  void makeDtm() {
    Heightfield& d = w_.dtm;
    d.cellX = s_.dtmCell;
    d.cellY = -s_.dtmCell;
    d.cols = int(std::ceil((domainHi_.x - domainLo_.x) / s_.dtmCell));
    d.rows = int(std::ceil((domainHi_.y - domainLo_.y) / s_.dtmCell));
    d.originX = domainLo_.x;
    d.originY = domainLo_.y + d.rows * s_.dtmCell;
    d.crs = "EPSG:2154";
    d.z.resize(size_t(d.cols) * d.rows);
    for (int j = 0; j < d.rows; ++j)
      for (int i = 0; i < d.cols; ++i) {
        const glm::dvec2 p = d.samplePosition(i, j);
        d.z[size_t(j) * d.cols + i] = float(w_.terrainZ(p.x, p.y));
      }
  }

  // The whole large city's DTM, on a lattice of largeDtmCell anchored at originXY (so a sample is
  // the same whatever the city's size), covering the street grid and the grass margin.
  void makeLargeDtm() {
    const double c = s_.largeDtmCell;
    const glm::dvec2 lo = grid_.lo() - glm::dvec2(s_.margin), hi = grid_.hi() + glm::dvec2(s_.margin);
    const long c0 = long(std::floor((lo.x - s_.originXY.x) / c)), c1 = long(std::ceil((hi.x - s_.originXY.x) / c));
    const long r0 = long(std::floor((lo.y - s_.originXY.y) / c)), r1 = long(std::ceil((hi.y - s_.originXY.y) / c));
    Heightfield& d = w_.dtm;
    d.cellX = c;
    d.cellY = -c;
    d.cols = int(c1 - c0);
    d.rows = int(r1 - r0);
    d.originX = s_.originXY.x + double(c0) * c;
    d.originY = s_.originXY.y + double(r1) * c;
    d.crs = "EPSG:2154";
    d.z.resize(size_t(d.cols) * d.rows);
    for (int j = 0; j < d.rows; ++j)
      for (int i = 0; i < d.cols; ++i) {
        const glm::dvec2 p = d.samplePosition(i, j);
        d.z[size_t(j) * d.cols + i] = float(w_.terrainZ(p.x, p.y));
      }
  }

  // Ground truth ground: a rectilinear grid whose lines include every kerb line, so each cell is
  // road, sidewalk or grass; sidewalks are raised by the kerb height and vertical kerb faces close
  // the steps. Cells do not share vertices across a step, but same-height neighbours compute the
  // same z at the same (x, y), so the surface stays watertight.
  void makeGround() {
    auto breaks = [&](bool alongX, double lo, double hi) {
      std::vector<double> b{lo, hi};
      for (const Street& st : w_.streets) {
        if (st.alongX != alongX) continue;
        for (double off : {-0.5 * g_.streetWidth, -0.5 * s_.roadWidth, 0.5 * s_.roadWidth, 0.5 * g_.streetWidth})
          b.push_back(st.centre + off);
      }
      std::sort(b.begin(), b.end());
      std::vector<double> out;
      for (size_t k = 0; k + 1 < b.size(); ++k) {
        const int n = std::max(1, int(std::ceil((b[k + 1] - b[k]) / s_.groundCell - 1e-9)));
        for (int m = 0; m < n; ++m) out.push_back(b[k] + (b[k + 1] - b[k]) * m / n);
      }
      out.push_back(b.back());
      return out;
    };
    const std::vector<double> xs = breaks(false, domainLo_.x, domainHi_.x);
    const std::vector<double> ys = breaks(true, domainLo_.y, domainHi_.y);
    const int nx = int(xs.size()) - 1, ny = int(ys.size()) - 1;
    const std::uint32_t sGrass = addSurface(w_.truth, {Material::Grass});
    const std::uint32_t sAsphalt = addSurface(w_.truth, {Material::Asphalt});
    const std::uint32_t sPaving = addSurface(w_.truth, {Material::Paving});
    const std::uint32_t sKerb = addSurface(w_.truth, {Material::Kerb});
    std::vector<int> kind(size_t(nx) * ny);  // 0 grass, 1 road, 2 sidewalk
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double cx = 0.5 * (xs[i] + xs[i + 1]), cy = 0.5 * (ys[j] + ys[j + 1]);
        kind[size_t(j) * nx + i] = w_.onRoad(cx, cy) ? 1 : w_.onSidewalk(cx, cy) ? 2 : 0;
      }
    auto offset = [&](int k) { return k == 2 ? s_.kerbHeight : 0.0; };
    const glm::dvec3 up(0, 0, 1);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int k = kind[size_t(j) * nx + i];
        const double h = offset(k);
        auto p = [&](int a, int b) { return glm::dvec3(xs[a], ys[b], w_.terrainZ(xs[a], ys[b]) + h); };
        addQuad(w_.truth, p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1), up,
                k == 1   ? sAsphalt
                : k == 2 ? sPaving
                         : sGrass);
        // Kerb faces towards the lower neighbour (right and top neighbours; left and bottom are
        // handled from the other side).
        if (i + 1 < nx) {
          const double h2 = offset(kind[size_t(j) * nx + i + 1]);
          if (h2 != h) {
            const double x = xs[i + 1];
            const double t0 = w_.terrainZ(x, ys[j]), t1 = w_.terrainZ(x, ys[j + 1]);
            addQuad(w_.truth, {x, ys[j], t0 + h}, {x, ys[j + 1], t1 + h}, {x, ys[j + 1], t1 + h2}, {x, ys[j], t0 + h2},
                    glm::dvec3(h > h2 ? 1.0 : -1.0, 0, 0), sKerb);
          }
        }
        if (j + 1 < ny) {
          const double h2 = offset(kind[size_t(j + 1) * nx + i]);
          if (h2 != h) {
            const double y = ys[j + 1];
            const double t0 = w_.terrainZ(xs[i], y), t1 = w_.terrainZ(xs[i + 1], y);
            addQuad(w_.truth, {xs[i], y, t0 + h}, {xs[i + 1], y, t1 + h}, {xs[i + 1], y, t1 + h2}, {xs[i], y, t0 + h2},
                    glm::dvec3(0, h > h2 ? 1.0 : -1.0, 0), sKerb);
          }
        }
      }
  }

  void makeBuildings() {
    // Lots: blocks of two rows; every lot touches a street (row 0 the south street, row 1 the north).
    std::vector<detail::Lot> lots;
    const double pitchX = g_.blockW + g_.streetWidth, pitchY = g_.blockD + g_.streetWidth;
    for (int bj = 0; bj < g_.nby; ++bj)
      for (int bi = 0; bi < g_.nbx; ++bi) {
        const glm::dvec2 b0 = g_.lo + glm::dvec2(g_.streetWidth + bi * pitchX, g_.streetWidth + bj * pitchY);
        for (const detail::Lot& lot : detail::blockLots(s_, b0, g_.blockW, g_.blockD, rng_)) lots.push_back(lot);
      }
    // Which lots are built: a seeded shuffle (Fisher-Yates with our own generator).
    std::vector<int> order(lots.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = int(k);
    for (size_t k = order.size(); k > 1; --k) std::swap(order[k - 1], order[size_t(rng_.next() % k)]);
    const int n = std::min<int>(o_.buildings, int(lots.size()));
    order.resize(size_t(n));
    std::sort(order.begin(), order.end());  // ids follow the streets, not the shuffle
    const int courtyardLot = order.empty() ? -1 : order[size_t(rng_.next() % order.size())];
    for (int index : order) makeBuilding(lots[size_t(index)], index == courtyardLot, "");
  }

  // A large city's ground-truth zone: every lot draws from its own generator (detail::lotDraw),
  // exactly as forEachFootprint does, so the footprints are the same ones.
  void makeLargeBuildings() {
    for (int j = tj0_; j <= tj1_; ++j)
      for (int i = ti0_; i <= ti1_; ++i) {
        Rng block = detail::blockRng(o_.seed, i, j);
        const std::vector<detail::Lot> lots =
            detail::blockLots(s_, grid_.blockCorner(i, j), grid_.blockW, grid_.blockD, block);
        for (size_t k = 0; k < lots.size(); ++k) {
          detail::LotDraw d = detail::lotDraw(s_, o_.seed, i, j, int(k));
          if (!d.built) continue;
          rng_ = d.rng;
          makeBuilding(lots[k], d.courtyard, detail::largeBuildingId(i, j, int(k)));
        }
      }
  }

  void makeBuilding(const detail::Lot& lot, bool courtyard, const std::string& id) {
    const glm::dvec2 origin = lot.origin, u = lot.u, v = lot.v;
    const detail::DrawnFootprint drawn = detail::drawFootprint(s_, lot, courtyard, rng_);
    const CellSet& cells = drawn.cells;
    const std::array<double, 4>& us = drawn.us;
    const std::array<double, 4>& vs = drawn.vs;
    auto world = [&](double a, double b) { return origin + a * u + b * v; };
    Building bld;
    bld.id = id.empty() ? "b" + std::to_string(w_.buildings.size() + 1) : id;
    bld.courtyard = drawn.shape == Shape::Courtyard;
    bld.rings = drawn.rings;
    bld.height = drawn.height;
    Footprint fp;
    fp.id = bld.id;
    fp.rings = bld.rings;
    fp.height = bld.height;
    // The LOD1 base exactly as the renderer computes it (heightfield.h): the ground-truth roof
    // then sits at the LOD1 roof height.
    bld.baseZ = w_.dtm.minUnder(bld.rings[0]).value_or(s_.baseElevation);
    bld.topZ = bld.baseZ + bld.height;
    double tMin = 1e30, tMax = -1e30;
    for (const auto& ring : bld.rings)
      for (glm::dvec2 p : ring) {
        tMin = std::min(tMin, w_.terrainZ(p.x, p.y));
        tMax = std::max(tMax, w_.terrainZ(p.x, p.y));
      }
    bld.groundFloorZ = tMax + s_.kerbHeight + 0.1;
    const int bIndex = int(w_.buildings.size());

    // Wall finish and colours per building.
    const double pick = rng_.uniform();
    const Material wallMat = pick < 0.6 ? Material::Plaster : pick < 0.85 ? Material::Brick : Material::Stone;
    glm::dvec3 tint;
    if (wallMat == Material::Plaster) {
      static const glm::dvec3 hues[] = {{0.93, 0.86, 0.70}, {0.90, 0.78, 0.66}, {0.85, 0.85, 0.80}, {0.92, 0.80, 0.62},
                                        {0.80, 0.84, 0.86}, {0.95, 0.90, 0.82}, {0.88, 0.72, 0.64}, {0.82, 0.86, 0.74}};
      tint = hues[rng_.integer(0, 7)] * rng_.uniform(0.92, 1.04);
    } else if (wallMat == Material::Brick) {
      tint = glm::dvec3(0.62, 0.30, 0.22) * rng_.uniform(0.85, 1.1);
    } else {
      tint = glm::dvec3(0.82, 0.78, 0.70) * rng_.uniform(0.9, 1.05);
    }
    const glm::dvec3 frameColor = rng_.chance(0.6) ? glm::dvec3(0.93, 0.93, 0.90) : glm::dvec3(0.40, 0.27, 0.18);
    const glm::dvec3 doorColor = glm::dvec3(rng_.uniform(0.25, 0.5), rng_.uniform(0.15, 0.3), rng_.uniform(0.08, 0.2));
    const bool balconies = rng_.chance(s_.balconyProbability);
    const Material roofMat = rng_.chance(0.5) ? Material::RoofGravel : Material::RoofTiles;

    // Vertical layout shared by all walls of the building, so wall grids meet at the corners.
    const double zb = tMin - 1.0, zt = bld.topZ;
    std::vector<double> floorZ;
    for (double z = bld.groundFloorZ; z + s_.sillHeight + s_.windowHeight <= zt - 0.5; z += s_.floorHeight)
      floorZ.push_back(z);
    bld.floors = int(floorZ.size());
    std::vector<double> wb{zb, zt};
    for (double fz : floorZ) {
      wb.push_back(fz + s_.sillHeight);
      wb.push_back(fz + s_.sillHeight + s_.windowHeight);
    }
    if (!floorZ.empty()) {
      wb.push_back(floorZ[0]);
      wb.push_back(floorZ[0] + s_.doorHeight);
    }
    std::sort(wb.begin(), wb.end());
    wb.erase(std::unique(wb.begin(), wb.end(), [](double a, double b) { return std::abs(a - b) < 1e-6; }), wb.end());

    const glm::dvec3 up(0.0, 0.0, 1.0);
    for (const auto& ring : bld.rings)
      for (size_t k = 0; k < ring.size(); ++k) {
        const glm::dvec2 a = ring[k], b = ring[(k + 1) % ring.size()];
        const double L = glm::length(b - a);
        const glm::dvec2 d2 = (b - a) / L;
        const glm::dvec3 dir(d2, 0.0), n(d2.y, -d2.x, 0.0);  // outward: right of the walk
        const glm::dvec2 mid = 0.5 * (a + b) + 1.5 * glm::dvec2(n);
        const bool street = w_.onSidewalk(mid.x, mid.y) || w_.onRoad(mid.x, mid.y);
        Surface wall{wallMat, bIndex, glm::dvec3(a, bld.groundFloorZ), dir, up, {L, zt - bld.groundFloorZ}, tint};
        wall.variant = std::uint32_t(bIndex);
        const std::uint32_t sWall = addSurface(w_.truth, wall);
        Surface reveal = wall;
        reveal.material = Material::Reveal;
        const std::uint32_t sReveal = addSurface(w_.truth, reveal);

        // Openings: bays centred on the wall.
        std::vector<Opening> openings;
        const int bays = int(std::floor((L - 1.6) / s_.bayWidth));
        std::vector<double> ub{0.0, L};
        for (int bay = 0; bay < bays; ++bay) {
          const double uc = 0.5 * L + (bay - 0.5 * (bays - 1)) * s_.bayWidth;
          for (size_t f = 0; f < floorZ.size(); ++f) {
            const bool door = f == 0 && street && bay == bays / 2;
            const double hw = 0.5 * (door ? s_.doorWidth : s_.windowWidth);
            const double w0 = door ? floorZ[f] : floorZ[f] + s_.sillHeight;
            const double w1 = door ? floorZ[f] + s_.doorHeight : w0 + s_.windowHeight;
            openings.push_back({uc - hw, uc + hw, w0, w1, door});
            ub.push_back(uc - hw);
            ub.push_back(uc + hw);
            if (balconies && street && f >= 1 && bay % 2 == 0) addBalcony(a, dir, n, uc, floorZ[f], L, bIndex, tint);
          }
        }
        std::sort(ub.begin(), ub.end());
        ub.erase(std::unique(ub.begin(), ub.end(), [](double x, double y) { return std::abs(x - y) < 1e-6; }),
                 ub.end());
        std::vector<std::uint32_t> openingSurface;
        for (const Opening& op : openings) {
          Surface s{op.door ? Material::Door : Material::Glass,
                    bIndex,
                    glm::dvec3(a + d2 * op.u0, op.w0) - s_.recessDepth * n,
                    dir,
                    up,
                    {op.u1 - op.u0, op.w1 - op.w0},
                    op.door ? doorColor : frameColor};
          openingSurface.push_back(addSurface(w_.truth, s));
        }
        // Wall grid: each cell is plain wall or part of an opening (recessed back face plus reveals
        // where the neighbour is wall).
        const int nu = int(ub.size()) - 1, nw = int(wb.size()) - 1;
        auto openingAt = [&](int iu, int iw) -> int {
          if (iu < 0 || iw < 0 || iu >= nu || iw >= nw) return -1;
          const double cu = 0.5 * (ub[iu] + ub[iu + 1]), cw = 0.5 * (wb[iw] + wb[iw + 1]);
          for (size_t q = 0; q < openings.size(); ++q)
            if (cu > openings[q].u0 && cu < openings[q].u1 && cw > openings[q].w0 && cw < openings[q].w1) return int(q);
          return -1;
        };
        auto P = [&](double uu, double ww, double depth) { return glm::dvec3(a + d2 * uu, ww) - depth * n; };
        const double r = s_.recessDepth;
        for (int iu = 0; iu < nu; ++iu)
          for (int iw = 0; iw < nw; ++iw) {
            const double ua = ub[iu], ubb = ub[iu + 1], wa = wb[iw], wbb = wb[iw + 1];
            const int op = openingAt(iu, iw);
            if (op < 0) {
              addQuad(w_.truth, P(ua, wa, 0), P(ubb, wa, 0), P(ubb, wbb, 0), P(ua, wbb, 0), n, sWall);
              continue;
            }
            addQuad(w_.truth, P(ua, wa, r), P(ubb, wa, r), P(ubb, wbb, r), P(ua, wbb, r), n,
                    openingSurface[size_t(op)]);
            if (openingAt(iu - 1, iw) != op)
              addQuad(w_.truth, P(ua, wa, 0), P(ua, wbb, 0), P(ua, wbb, r), P(ua, wa, r), dir, sReveal);
            if (openingAt(iu + 1, iw) != op)
              addQuad(w_.truth, P(ubb, wa, 0), P(ubb, wbb, 0), P(ubb, wbb, r), P(ubb, wa, r), -dir, sReveal);
            if (openingAt(iu, iw - 1) != op)
              addQuad(w_.truth, P(ua, wa, 0), P(ubb, wa, 0), P(ubb, wa, r), P(ua, wa, r), up, sReveal);
            if (openingAt(iu, iw + 1) != op)
              addQuad(w_.truth, P(ua, wbb, 0), P(ubb, wbb, 0), P(ubb, wbb, r), P(ua, wbb, r), -up, sReveal);
          }
      }
    // Flat roof at the LOD1 height, one quad per cell of the shape.
    Surface roof{roofMat, bIndex, glm::dvec3(origin, zt), glm::dvec3(u, 0.0), glm::dvec3(v, 0.0), {}, tint};
    const std::uint32_t sRoof = addSurface(w_.truth, roof);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (cells[size_t(i)][size_t(j)])
          addQuad(w_.truth, glm::dvec3(world(us[i], vs[j]), zt), glm::dvec3(world(us[i + 1], vs[j]), zt),
                  glm::dvec3(world(us[i + 1], vs[j + 1]), zt), glm::dvec3(world(us[i], vs[j + 1]), zt), up, sRoof);
    w_.footprints.push_back(fp);
    w_.buildings.push_back(bld);
  }

  // A slab protruding from the wall under a window, with a solid parapet on three sides.
  void addBalcony(glm::dvec2 a, glm::dvec3 dir, glm::dvec3 n, double uc, double floorZ, double L, int bIndex,
                  glm::dvec3 tint) {
    const double hw = 0.5 * s_.windowWidth + 0.4;
    if (uc - hw < 0.3 || uc + hw > L - 0.3) return;
    Surface s{Material::Balcony,
              bIndex,
              glm::dvec3(a, floorZ) + dir * (uc - hw),
              dir,
              glm::dvec3(0, 0, 1),
              {2.0 * hw, s_.balconyParapet},
              tint};
    const std::uint32_t sb = addSurface(w_.truth, s);
    const glm::dvec3 up(0, 0, 1), base = glm::dvec3(a, floorZ) + dir * uc;
    const double d = s_.balconyDepth, t = s_.balconyThickness, h = s_.balconyParapet, pt = 0.05;
    addBox(w_.truth, base + n * (0.5 * d) - up * (0.5 * t), dir, n, up, {hw, 0.5 * d, 0.5 * t}, sb);
    addBox(w_.truth, base + n * (d - 0.5 * pt) + up * (0.5 * h), dir, n, up, {hw, 0.5 * pt, 0.5 * h}, sb);
    for (double side : {-1.0, 1.0})
      addBox(w_.truth, base + dir * (side * (hw - 0.5 * pt)) + n * (0.5 * d) + up * (0.5 * h), dir, n, up,
             {0.5 * pt, 0.5 * d - pt, 0.5 * h}, sb);
    Aabb box;
    box.extend(base - dir * hw - up * t);
    box.extend(base + dir * hw + n * d + up * h);
    balconyBoxes_.push_back(box);
  }

  bool clearOfBuildings(glm::dvec2 p, double radius) const {
    for (const Building& b : w_.buildings) {
      if (insideRings(b.rings, p)) return false;
      for (const auto& ring : b.rings)
        for (size_t k = 0; k < ring.size(); ++k) {
          const glm::dvec2 a = ring[k], c = ring[(k + 1) % ring.size()];
          const double t = glm::clamp(glm::dot(p - a, c - a) / glm::dot(c - a, c - a), 0.0, 1.0);
          if (glm::length(p - (a + t * (c - a))) < radius) return false;
        }
    }
    return true;
  }

  void addTree(glm::dvec2 p, double crownRadius, double trunkHeight) {
    const double z = w_.groundZ(p.x, p.y);
    const glm::dvec3 crownCentre(p, z + trunkHeight + 0.8 * crownRadius);
    for (const Aabb& box : balconyBoxes_) {
      const glm::dvec3 q = glm::clamp(crownCentre, box.lo, box.hi);
      if (glm::length(q - crownCentre) < crownRadius + 0.3) return;
    }
    Surface trunk{Material::TreeTrunk};
    trunk.origin = glm::dvec3(p, z);
    const std::uint32_t sTrunk = addSurface(w_.trees, trunk);
    Surface crown{Material::TreeCrown};
    crown.origin = crownCentre;
    crown.tint = glm::dvec3(0.30, 0.45, 0.18) * rng_.uniform(0.8, 1.15);
    const std::uint32_t sCrown = addSurface(w_.trees, crown);
    // Trunk: octagonal prism, sunk a little into the ground.
    const int sides = 8;
    const double rt = 0.15;
    for (int k = 0; k < sides; ++k) {
      const double a0 = 6.283185307179586 * k / sides, a1 = 6.283185307179586 * (k + 1) / sides;
      const glm::dvec2 e0(std::cos(a0), std::sin(a0)), e1(std::cos(a1), std::sin(a1));
      const glm::dvec3 out(0.5 * (e0 + e1), 0.0);
      addQuad(w_.trees, glm::dvec3(p + rt * e0, z - 0.2), glm::dvec3(p + rt * e1, z - 0.2),
              glm::dvec3(p + rt * e1, z + trunkHeight + 0.5 * crownRadius),
              glm::dvec3(p + rt * e0, z + trunkHeight + 0.5 * crownRadius), out, sTrunk);
    }
    // Crown: a latitude-longitude sphere, jittered radius so it is not a perfect ball.
    const int lat = 6, lon = 10;
    auto vertex = [&](int i, int j) {
      const double th = 3.141592653589793 * i / lat, ph = 6.283185307179586 * (j % lon) / lon;
      const double rr = crownRadius * (1.0 + 0.12 * (detail::hash01(i, j % lon, std::int64_t(p.x * 10), 77) - 0.5));
      return crownCentre + rr * glm::dvec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    };
    for (int i = 0; i < lat; ++i)
      for (int j = 0; j < lon; ++j) {
        const glm::dvec3 a = vertex(i, j), b = vertex(i + 1, j), c = vertex(i + 1, j + 1), d = vertex(i, j + 1);
        const glm::dvec3 out = 0.25 * (a + b + c + d) - crownCentre;
        if (i > 0) detail::addTriangle(w_.trees, a, b, d, out, sCrown);
        if (i + 1 < lat) detail::addTriangle(w_.trees, b, c, d, out, sCrown);
      }
  }

  void makeTrees() {
    // Street trees on both sidewalks, a metre from the kerb, away from crossings.
    for (const Street& st : w_.streets)
      for (double side : {-1.0, 1.0})
        for (double t = st.from + g_.streetWidth + 2.0; t < st.to - g_.streetWidth - 2.0; t += s_.treeSpacing) {
          const double along = t + rng_.uniform(-1.5, 1.5);
          const double lateral = st.centre + side * (0.5 * s_.roadWidth + 1.0);
          const glm::dvec2 p = st.alongX ? glm::dvec2(along, lateral) : glm::dvec2(lateral, along);
          if (!w_.onSidewalk(p.x, p.y) || w_.onRoad(p.x, p.y)) continue;
          const double r = rng_.uniform(1.2, 1.6), h = rng_.uniform(2.6, 3.4);
          if (clearOfBuildings(p, r + 0.2)) addTree(p, r, h);
        }
    // A few trees in yards and courtyards.
    for (int k = 0; k < 3 * std::max(1, int(w_.buildings.size()) / 4); ++k) {
      const glm::dvec2 p(rng_.uniform(g_.lo.x, g_.hi.x), rng_.uniform(g_.lo.y, g_.hi.y));
      if (w_.onSidewalk(p.x, p.y) || w_.onRoad(p.x, p.y)) continue;
      const double r = rng_.uniform(1.5, 2.5);
      if (clearOfBuildings(p, r + 0.3)) addTree(p, r, rng_.uniform(2.5, 4.0));
    }
  }

  void makeParkedCars() {
    for (const Street& st : w_.streets)
      for (int k = 0; k < s_.parkedCarsPerStreet; ++k) {
        const double along = rng_.uniform(st.from + g_.streetWidth + 3.0, st.to - g_.streetWidth - 3.0);
        const double side = rng_.chance(0.5) ? -1.0 : 1.0;
        const double lateral = st.centre + side * (0.5 * s_.roadWidth - 1.1);
        const glm::dvec2 p = st.alongX ? glm::dvec2(along, lateral) : glm::dvec2(lateral, along);
        if (!w_.onRoad(p.x, p.y)) continue;
        const glm::dvec2 dir = st.alongX ? glm::dvec2(side, 0.0) : glm::dvec2(0.0, side);
        const glm::dvec3 color(rng_.uniform(0.1, 0.9), rng_.uniform(0.1, 0.9), rng_.uniform(0.1, 0.9));
        detail::addCar(w_.parkedCars, glm::dvec3(p, w_.groundZ(p.x, p.y)), dir, color);
      }
  }
};

}  // namespace

double World::terrainZ(double x, double y) const {
  const CitySettings& s = options.city;
  const double lx = x - origin.x, ly = y - origin.y;
  // A gentle tilt plus two undulations: a few metres of relief over the city, slopes under 6 %.
  return s.baseElevation + 0.012 * lx - 0.008 * ly +
         s.reliefAmplitude * std::sin(lx / 41.0 + phase[0]) * std::cos(ly / 33.0 + phase[1]) +
         0.5 * s.reliefAmplitude * std::sin((lx + ly) / 23.0 + phase[2]);
}

bool World::onRoad(double x, double y) const {
  for (const Street& st : streets) {
    const double across = st.alongX ? y : x, along = st.alongX ? x : y;
    if (along >= st.from && along <= st.to && std::abs(across - st.centre) <= 0.5 * roadWidth) return true;
  }
  return false;
}

bool World::onSidewalk(double x, double y) const {
  if (onRoad(x, y)) return false;
  for (const Street& st : streets) {
    const double across = st.alongX ? y : x, along = st.alongX ? x : y;
    if (along >= st.from && along <= st.to && std::abs(across - st.centre) <= 0.5 * streetWidth) return true;
  }
  return false;
}

double World::groundZ(double x, double y) const { return terrainZ(x, y) + (onSidewalk(x, y) ? kerbHeight : 0.0); }

bool World::insideBuilding(double x, double y) const {
  for (const Building& b : buildings)
    if (insideRings(b.rings, {x, y})) return true;
  return false;
}

World buildWorld(const DemoOptions& options) { return CityBuilder(options).build(); }

}  // namespace hv::demo
