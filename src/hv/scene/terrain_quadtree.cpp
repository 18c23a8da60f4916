#include "hv/scene/terrain_quadtree.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <set>
#include <stdexcept>
#include <string>

namespace hv {

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// The overview sample coordinate of level sample k (step `step`): the lower of its two overview
// neighbours and the weight t of the upper one. Within half an overview cell of the raster's edge
// q lies outside the overview's sample centres: t is then outside [0, 1] (linear extrapolation
// from the two outermost samples, exact for a plane), clamped to [-0.5, 1.5].
void overviewCoordinate(const OverviewAxis& a, int step, int k, int& lower, double& t) {
  const double p = double(std::min(std::int64_t(k) * step, std::int64_t(a.fullCount) - 1));
  const double q = (p + 0.5) / a.ratio - 0.5;
  if (a.overviewCount < 2) {
    lower = 0, t = 0.0;
    return;
  }
  lower = std::clamp(int(std::floor(q)), 0, a.overviewCount - 2);
  t = std::clamp(q - lower, -0.5, 1.5);
}

}  // namespace

OverviewSpan overviewSpan(const OverviewAxis& axis, int step, int k0, int n) {
  int lo = 0, hi = 0;
  double t = 0.0;
  overviewCoordinate(axis, step, k0, lo, t);
  overviewCoordinate(axis, step, k0 + n - 1, hi, t);
  return {lo, std::min(hi + 1, axis.overviewCount - 1)};
}

std::vector<float> resampleOverview(const std::vector<float>& window, const OverviewAxis& ax, const OverviewAxis& ay,
                                    OverviewSpan spanX, OverviewSpan spanY, int step, int kx0, int ky0, int nx,
                                    int ny) {
  const int wcols = spanX.hi - spanX.lo + 1, wrows = spanY.hi - spanY.lo + 1;
  if (window.size() != size_t(wcols) * size_t(wrows))
    throw std::invalid_argument("resampleOverview: window of " + std::to_string(window.size()) + " samples for " +
                                std::to_string(wcols) + " x " + std::to_string(wrows));
  std::vector<int> ix(static_cast<size_t>(nx)), iy(static_cast<size_t>(ny));
  std::vector<double> tx(static_cast<size_t>(nx)), ty(static_cast<size_t>(ny));
  for (int a = 0; a < nx; ++a) {
    overviewCoordinate(ax, step, kx0 + a, ix[a], tx[a]);
    ix[a] -= spanX.lo;
  }
  for (int b = 0; b < ny; ++b) {
    overviewCoordinate(ay, step, ky0 + b, iy[b], ty[b]);
    iy[b] -= spanY.lo;
  }
  std::vector<float> out(size_t(nx) * size_t(ny), kNaN);
  for (int b = 0; b < ny; ++b)
    for (int a = 0; a < nx; ++a) {
      double sum = 0.0, weight = 0.0;
      const float* row0 = &window[size_t(std::min(iy[b], wrows - 1)) * wcols];
      const float* row1 = &window[size_t(std::min(iy[b] + 1, wrows - 1)) * wcols];
      const int i0 = std::min(ix[a], wcols - 1), i1 = std::min(ix[a] + 1, wcols - 1);
      const float v[4] = {row0[i0], row0[i1], row1[i0], row1[i1]};
      if (!std::isnan(v[0]) && !std::isnan(v[1]) && !std::isnan(v[2]) && !std::isnan(v[3])) {
        const double u = tx[a], w = ty[b];  // extrapolation allowed (weights may be negative)
        out[size_t(b) * nx + a] =
            float((1 - u) * (1 - w) * v[0] + u * (1 - w) * v[1] + (1 - u) * w * v[2] + u * w * v[3]);
        continue;
      }
      // A no-data neighbour: interpolation only, over the neighbours with data.
      const double u = std::clamp(tx[a], 0.0, 1.0), w = std::clamp(ty[b], 0.0, 1.0);
      const double weights[4] = {(1 - u) * (1 - w), u * (1 - w), (1 - u) * w, u * w};
      for (int c = 0; c < 4; ++c) {
        if (weights[c] <= 0.0 || std::isnan(v[c])) continue;
        sum += weights[c] * v[c];
        weight += weights[c];
      }
      if (weight > 0.0) out[size_t(b) * nx + a] = float(sum / weight);
    }
  return out;
}

std::vector<float> averageBlocks(const std::vector<float>& z, int cols, int rows, int factor, int& outCols,
                                 int& outRows) {
  outCols = (cols + factor - 1) / factor;
  outRows = (rows + factor - 1) / factor;
  std::vector<double> sum(size_t(outCols) * outRows, 0.0);
  std::vector<std::uint32_t> count(sum.size(), 0);
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) {
      const float v = z[size_t(j) * cols + i];
      if (std::isnan(v)) continue;
      const size_t o = size_t(j / factor) * outCols + size_t(i / factor);
      sum[o] += v;
      ++count[o];
    }
  std::vector<float> out(sum.size(), kNaN);
  for (size_t o = 0; o < out.size(); ++o)
    if (count[o]) out[o] = float(sum[o] / count[o]);
  return out;
}

HeightfieldTerrainSource::HeightfieldTerrainSource(Heightfield field) : field_(std::move(field)) {
  if (field_.cols < 2 || field_.rows < 2 || field_.z.size() != size_t(field_.cols) * field_.rows)
    throw std::invalid_argument("HeightfieldTerrainSource: expected at least 2 x 2 samples, got " +
                                std::to_string(field_.cols) + " x " + std::to_string(field_.rows));
  grid_ = {field_.cols, field_.rows, field_.originX, field_.originY, field_.cellX, field_.cellY};
}

const HeightfieldTerrainSource::Overview& HeightfieldTerrainSource::overview(int ratio) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  int have = 1;
  for (const auto& o : pyramid_) have = o->ratio;
  while (have < ratio) {
    auto next = std::make_unique<Overview>();
    next->ratio = have * 2;
    if (pyramid_.empty())
      next->z = averageBlocks(field_.z, field_.cols, field_.rows, 2, next->cols, next->rows);
    else
      next->z =
          averageBlocks(pyramid_.back()->z, pyramid_.back()->cols, pyramid_.back()->rows, 2, next->cols, next->rows);
    have = next->ratio;
    pyramid_.push_back(std::move(next));
  }
  for (const auto& o : pyramid_)
    if (o->ratio == ratio) return *o;
  throw std::invalid_argument("HeightfieldTerrainSource: step " + std::to_string(ratio) + " is not a power of two");
}

std::vector<float> HeightfieldTerrainSource::levelSamples(int step, int kx0, int ky0, int nx, int ny) const {
  const float* z = field_.z.data();
  int cols = field_.cols, rows = field_.rows, ratio = 1;
  if (step > 1) {
    const Overview& o = overview(step);
    z = o.z.data(), cols = o.cols, rows = o.rows, ratio = o.ratio;
  }
  const OverviewAxis ax{field_.cols, cols, double(ratio)}, ay{field_.rows, rows, double(ratio)};
  const OverviewSpan sx = overviewSpan(ax, step, kx0, nx), sy = overviewSpan(ay, step, ky0, ny);
  std::vector<float> window;
  window.reserve(size_t(sx.hi - sx.lo + 1) * size_t(sy.hi - sy.lo + 1));
  for (int j = sy.lo; j <= sy.hi; ++j)
    for (int i = sx.lo; i <= sx.hi; ++i) window.push_back(z[size_t(j) * cols + i]);
  return resampleOverview(window, ax, ay, sx, sy, step, kx0, ky0, nx, ny);
}

TerrainQuadtree::TerrainQuadtree(std::shared_ptr<const TerrainSource> source, TerrainTileOptions options)
    : source_(std::move(source)), options_(options) {
  if (!source_) throw std::invalid_argument("TerrainQuadtree: no source");
  if (options_.tileCells < 2 || (options_.tileCells & (options_.tileCells - 1)) != 0)
    throw std::invalid_argument("TerrainQuadtree: tileCells must be a power of two >= 2, got " +
                                std::to_string(options_.tileCells));
  grid_ = source_->grid();
  if (grid_.cols < 2 || grid_.rows < 2) throw std::invalid_argument("TerrainQuadtree: expected at least 2 x 2 samples");
  const std::int64_t span = std::max(grid_.cols, grid_.rows) - 1;
  while ((std::int64_t(options_.tileCells) << maxLevel_) < span) ++maxLevel_;
}

int TerrainQuadtree::lastSampleX(int level) const {
  const int s = step(level);
  return (grid_.cols - 1 + s - 1) / s;
}
int TerrainQuadtree::lastSampleY(int level) const {
  const int s = step(level);
  return (grid_.rows - 1 + s - 1) / s;
}

TerrainNodeId TerrainQuadtree::makeId(int level, int tx, int ty) {
  return (TerrainNodeId(level) << 56) | (TerrainNodeId(ty) << 28) | TerrainNodeId(tx);
}

bool TerrainQuadtree::exists(TerrainNodeId id) const {
  const int l = levelOf(id);
  if (l < 0 || l > maxLevel_) return false;
  const std::int64_t n = options_.tileCells;
  return txOf(id) * n < lastSampleX(l) && tyOf(id) * n < lastSampleY(l);
}

std::vector<TerrainNodeId> TerrainQuadtree::children(TerrainNodeId id) const {
  std::vector<TerrainNodeId> out;
  const int l = levelOf(id);
  if (l >= maxLevel_) return out;
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx) {
      const TerrainNodeId c = makeId(l + 1, 2 * txOf(id) + dx, 2 * tyOf(id) + dy);
      if (exists(c)) out.push_back(c);
    }
  return out;
}

TerrainNodeId TerrainQuadtree::parent(TerrainNodeId id) const {
  const int l = levelOf(id);
  return l == 0 ? id : makeId(l - 1, txOf(id) / 2, tyOf(id) / 2);
}

double TerrainQuadtree::samplePos(int level, int k, bool yAxis) const {
  const std::int64_t p = std::int64_t(k) * step(level);
  return double(std::min<std::int64_t>(p, (yAxis ? grid_.rows : grid_.cols) - 1));
}

double TerrainQuadtree::surfaceAt(const TerrainTile& t, double i, double j) const {
  const int s = step(t.level);
  const int a = std::clamp(int(std::floor(i / s)) - t.kx0, 0, t.nx - 1);
  const int b = std::clamp(int(std::floor(j / s)) - t.ky0, 0, t.ny - 1);
  const double x0 = samplePos(t.level, t.kx0 + a, false), x1 = samplePos(t.level, t.kx0 + a + 1, false);
  const double y0 = samplePos(t.level, t.ky0 + b, true), y1 = samplePos(t.level, t.ky0 + b + 1, true);
  constexpr double kSlack = 1e-9;
  if (i < x0 - kSlack || i > x1 + kSlack || j < y0 - kSlack || j > y1 + kSlack) return kNaN;
  const double u = std::clamp((i - x0) / (x1 - x0), 0.0, 1.0), v = std::clamp((j - y0) / (y1 - y0), 0.0, 1.0);
  const int w = t.nx + 1;
  const double z00 = t.z[size_t(b) * w + a], z10 = t.z[size_t(b) * w + a + 1];
  const double z01 = t.z[size_t(b + 1) * w + a], z11 = t.z[size_t(b + 1) * w + a + 1];
  if (std::isnan(z00) || std::isnan(z10) || std::isnan(z01) || std::isnan(z11)) return kNaN;
  // The cell's two triangles, split along (a, b)-(a + 1, b + 1) as in tileMesh.
  if (u >= v) return z00 + u * (z10 - z00) + v * (z11 - z10);
  return z00 + v * (z01 - z00) + u * (z11 - z01);
}

const TerrainTile& TerrainQuadtree::tile(TerrainNodeId id) {
  if (const auto it = tiles_.find(id); it != tiles_.end()) return it->second;
  return tiles_.emplace(id, readTile(id)).first->second;
}

glm::ivec2 TerrainQuadtree::tileCellCount(TerrainNodeId id) const {
  const int l = levelOf(id), n = options_.tileCells;
  return {std::min(n, lastSampleX(l) - txOf(id) * n), std::min(n, lastSampleY(l) - tyOf(id) * n)};
}

glm::dvec4 TerrainQuadtree::footprint(TerrainNodeId id) const {
  const int l = levelOf(id), n = options_.tileCells;
  const glm::ivec2 cells = tileCellCount(id);
  const int kx0 = txOf(id) * n, ky0 = tyOf(id) * n;
  const glm::dvec2 a = grid_.position(samplePos(l, kx0, false), samplePos(l, ky0, true));
  const glm::dvec2 b = grid_.position(samplePos(l, kx0 + cells.x, false), samplePos(l, ky0 + cells.y, true));
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::max(a.x, b.x), std::max(a.y, b.y)};
}

TerrainTile TerrainQuadtree::readTile(TerrainNodeId id) const {
  if (!exists(id)) throw std::invalid_argument("TerrainQuadtree::tile: no node " + std::to_string(id));
  TerrainTile t;
  t.level = levelOf(id), t.tx = txOf(id), t.ty = tyOf(id);
  const int n = options_.tileCells, l = t.level;
  t.kx0 = t.tx * n, t.ky0 = t.ty * n;
  t.nx = std::min(n, lastSampleX(l) - t.kx0);
  t.ny = std::min(n, lastSampleY(l) - t.ky0);
  t.z = source_->levelSamples(step(l), t.kx0, t.ky0, t.nx + 1, t.ny + 1);
  for (int b = 0; b <= t.ny; ++b)
    for (int a = 0; a <= t.nx; ++a) {
      const float v = t.z[size_t(b) * (t.nx + 1) + a];
      if (std::isnan(v)) continue;
      const glm::dvec2 xy = grid_.position(samplePos(l, t.kx0 + a, false), samplePos(l, t.ky0 + b, true));
      t.bounds.extend(glm::dvec3(xy, double(v)));
    }
  if (l < maxLevel_ && !t.bounds.empty()) {
    // The children's samples over this tile: level l + 1, every sample between the tile's borders.
    const int cx0 = 2 * t.kx0, cy0 = 2 * t.ky0;
    const int cnx = std::min(2 * (t.kx0 + t.nx), lastSampleX(l + 1)) - cx0 + 1;
    const int cny = std::min(2 * (t.ky0 + t.ny), lastSampleY(l + 1)) - cy0 + 1;
    const std::vector<float> fine = source_->levelSamples(step(l + 1), cx0, cy0, cnx, cny);
    for (int b = 0; b < cny; ++b)
      for (int a = 0; a < cnx; ++a) {
        const float v = fine[size_t(b) * cnx + a];
        if (std::isnan(v)) continue;
        const double z = surfaceAt(t, samplePos(l + 1, cx0 + a, false), samplePos(l + 1, cy0 + b, true));
        if (!std::isnan(z)) t.error = std::max(t.error, std::abs(z - double(v)));
      }
  }
  return t;
}

double TerrainQuadtree::screenSpaceError(TerrainNodeId id, const Camera& camera) {
  return screenSpaceError(tile(id), camera);
}

double TerrainQuadtree::screenSpaceError(const TerrainTile& t, const Camera& camera) {
  if (t.bounds.empty()) return 0.0;
  const glm::dvec3 c = camera.center;
  const glm::dvec3 d = glm::max(glm::max(t.bounds.lo - c, c - t.bounds.hi), glm::dvec3(0.0));
  const double distance = std::max({glm::length(d), 1e-3 * glm::length(t.bounds.size()), 1e-6});
  return t.error * std::max(camera.focal.x, camera.focal.y) / distance;
}

int TerrainQuadtree::estimatedTriangles(TerrainNodeId id) const {
  const int l = levelOf(id), n = options_.tileCells;
  const int nx = std::min(n, lastSampleX(l) - txOf(id) * n), ny = std::min(n, lastSampleY(l) - tyOf(id) * n);
  return 2 * nx * ny + 4 * (nx + ny);
}

std::vector<TerrainNodeId> TerrainQuadtree::select(const Camera& camera, double tolerancePx) {
  return select(std::vector<Camera>{camera}, tolerancePx, std::numeric_limits<std::size_t>::max()).nodes;
}

TerrainSelection TerrainQuadtree::select(const std::vector<Camera>& cameras, double tolerancePx,
                                         std::size_t triangleBudget) {
  auto priority = [&](TerrainNodeId id) {
    if (cameras.empty()) return tile(id).error;
    double worst = 0.0;
    for (const Camera& c : cameras) worst = std::max(worst, screenSpaceError(id, c));
    return worst;
  };
  auto refinable = [&](TerrainNodeId id, double p) {
    if (levelOf(id) >= maxLevel_ || tile(id).bounds.empty()) return false;
    return cameras.empty() ? p > 0.0 : p > tolerancePx;
  };
  TerrainSelection out;
  std::set<TerrainNodeId> chosen{root()};
  std::size_t triangles = std::size_t(estimatedTriangles(root()));
  std::priority_queue<std::pair<double, TerrainNodeId>> queue;
  if (const double p = priority(root()); refinable(root(), p)) queue.push({p, root()});
  while (!queue.empty()) {
    const TerrainNodeId id = queue.top().second;
    queue.pop();
    const std::vector<TerrainNodeId> kids = children(id);
    std::int64_t delta = -estimatedTriangles(id);
    for (TerrainNodeId k : kids) delta += estimatedTriangles(k);
    if (triangleBudget != std::numeric_limits<std::size_t>::max() &&
        std::int64_t(triangles) + delta > std::int64_t(triangleBudget)) {
      out.budgetLimited = true;
      continue;  // a smaller refinement further down the queue may still fit
    }
    triangles = std::size_t(std::int64_t(triangles) + delta);
    chosen.erase(id);
    for (TerrainNodeId k : kids) {
      chosen.insert(k);
      if (const double p = priority(k); refinable(k, p)) queue.push({p, k});
    }
  }
  out.nodes.assign(chosen.begin(), chosen.end());
  out.triangles = triangles;
  out.coarsestLevel = maxLevel_;
  for (TerrainNodeId id : out.nodes) {
    out.coarsestLevel = std::min(out.coarsestLevel, levelOf(id));
    out.finestLevel = std::max(out.finestLevel, levelOf(id));
  }
  return out;
}

double TerrainQuadtree::skirtDepth(TerrainNodeId id) {
  std::vector<const TerrainTile*> ancestors;
  for (TerrainNodeId a = id; levelOf(a) > 0;) {
    a = parent(a);
    ancestors.push_back(&tile(a));
  }
  return skirtDepth(tile(id), ancestors);
}

double TerrainQuadtree::skirtDepth(const TerrainTile& t, const std::vector<const TerrainTile*>& ancestors) const {
  const int l = t.level;
  double depth = options_.skirtMarginCells * step(l) * std::max(std::abs(grid_.cellX), std::abs(grid_.cellY));
  depth += t.error;
  // The tile's border samples, in full-resolution sample coordinates, with their heights.
  std::vector<glm::dvec3> border;
  const int w = t.nx + 1;
  auto add = [&](int a, int b) {
    const float v = t.z[size_t(b) * w + a];
    if (!std::isnan(v)) border.emplace_back(samplePos(l, t.kx0 + a, false), samplePos(l, t.ky0 + b, true), double(v));
  };
  for (int a = 0; a <= t.nx; ++a) add(a, 0), add(a, t.ny);
  for (int b = 1; b < t.ny; ++b) add(0, b), add(t.nx, b);
  double above = 0.0;
  for (const TerrainTile* coarse : ancestors) {
    for (const glm::dvec3& p : border) {
      const double z = surfaceAt(*coarse, p.x, p.y);
      if (!std::isnan(z)) above = std::max(above, p.z - z);
    }
  }
  return depth + above;
}

Mesh TerrainQuadtree::tileMesh(TerrainNodeId id, bool skirts) {
  const double depth = skirts ? skirtDepth(id) : 0.0;
  return tileMesh(tile(id), skirts, depth);
}

Mesh TerrainQuadtree::tileMesh(const TerrainTile& t, bool skirts, double depth) const {
  Mesh mesh;
  const int w = t.nx + 1, h = t.ny + 1, l = t.level;
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> vertex(size_t(w) * h, kNone);
  for (int b = 0; b < h; ++b)
    for (int a = 0; a < w; ++a) {
      const float v = t.z[size_t(b) * w + a];
      if (std::isnan(v)) continue;
      vertex[size_t(b) * w + a] = std::uint32_t(mesh.positions.size());
      const glm::dvec2 xy = grid_.position(samplePos(l, t.kx0 + a, false), samplePos(l, t.ky0 + b, true));
      mesh.positions.emplace_back(xy.x, xy.y, double(v));
    }
  // Winding as Heightfield::toMesh: counter-clockwise seen from above.
  const bool flip = (grid_.cellX * grid_.cellY) < 0.0;
  for (int b = 0; b + 1 < h; ++b)
    for (int a = 0; a + 1 < w; ++a) {
      const std::uint32_t v00 = vertex[size_t(b) * w + a], v10 = vertex[size_t(b) * w + a + 1];
      const std::uint32_t v01 = vertex[size_t(b + 1) * w + a], v11 = vertex[size_t(b + 1) * w + a + 1];
      if (v00 == kNone || v10 == kNone || v01 == kNone || v11 == kNone) continue;
      mesh.triangles.push_back(flip ? glm::uvec3(v00, v11, v10) : glm::uvec3(v00, v10, v11));
      mesh.triangles.push_back(flip ? glm::uvec3(v00, v01, v11) : glm::uvec3(v00, v11, v01));
    }
  if (!skirts) return mesh;
  // Skirts along the borders shared with other tiles (none on the raster's edge: no neighbour, no
  // crack), facing away from the tile.
  const double sx = grid_.cellX > 0 ? 1.0 : -1.0, sy = grid_.cellY > 0 ? 1.0 : -1.0;
  struct Side {
    bool shared;
    int a0, b0, da, db, count;
    glm::dvec3 outward;
  };
  const Side sides[4] = {{t.ky0 > 0, 0, 0, 1, 0, w, {0.0, -sy, 0.0}},                          // row 0
                         {t.ky0 + t.ny < lastSampleY(l), 0, h - 1, 1, 0, w, {0.0, sy, 0.0}},   // last row
                         {t.kx0 > 0, 0, 0, 0, 1, h, {-sx, 0.0, 0.0}},                          // column 0
                         {t.kx0 + t.nx < lastSampleX(l), w - 1, 0, 0, 1, h, {sx, 0.0, 0.0}}};  // last column
  for (const Side& side : sides) {
    if (!side.shared) continue;
    std::vector<std::uint32_t> bottom(size_t(side.count), kNone);
    auto top = [&](int k) { return vertex[size_t(side.b0 + k * side.db) * w + side.a0 + k * side.da]; };
    auto lowered = [&](int k) {
      if (bottom[k] == kNone) {
        bottom[k] = std::uint32_t(mesh.positions.size());
        const glm::dvec3 p = mesh.positions[top(k)];
        mesh.positions.emplace_back(p.x, p.y, p.z - depth);
      }
      return bottom[k];
    };
    for (int k = 0; k + 1 < side.count; ++k) {
      const std::uint32_t p = top(k), q = top(k + 1);
      if (p == kNone || q == kNone) continue;
      const std::uint32_t pb = lowered(k), qb = lowered(k + 1);
      const glm::dvec3 normal =
          glm::cross(mesh.positions[q] - mesh.positions[p], mesh.positions[qb] - mesh.positions[p]);
      if (glm::dot(normal, side.outward) >= 0.0) {
        mesh.triangles.emplace_back(p, q, qb);
        mesh.triangles.emplace_back(p, qb, pb);
      } else {
        mesh.triangles.emplace_back(p, qb, q);
        mesh.triangles.emplace_back(p, pb, qb);
      }
    }
  }
  return mesh;
}

Mesh TerrainQuadtree::mesh(const std::vector<TerrainNodeId>& ids, bool skirts) {
  Mesh out;
  for (TerrainNodeId id : ids) out.append(tileMesh(id, skirts));
  return out;
}

Heightfield TerrainQuadtree::levelHeightfield(int level) const {
  if (level < 0 || level > maxLevel_)
    throw std::invalid_argument("TerrainQuadtree::levelHeightfield: no level " + std::to_string(level));
  const int s = step(level);
  Heightfield f;
  f.cols = (grid_.cols - 1) / s + 1;
  f.rows = (grid_.rows - 1) / s + 1;
  f.cellX = grid_.cellX * s;
  f.cellY = grid_.cellY * s;
  // Sample i of the level sits on full-resolution sample i s: originX + (i s + 0.5) cellX.
  f.originX = grid_.originX + 0.5 * grid_.cellX - 0.5 * f.cellX;
  f.originY = grid_.originY + 0.5 * grid_.cellY - 0.5 * f.cellY;
  f.z = source_->levelSamples(s, 0, 0, f.cols, f.rows);
  return f;
}

}  // namespace hv
