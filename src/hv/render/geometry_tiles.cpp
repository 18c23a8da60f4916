#include "hv/render/geometry_tiles.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace hv::render {

int TileGridXY::cellOf(glm::dvec2 p) const {
  const double fx = (p.x - origin.x) / cell, fy = (p.y - origin.y) / cell;
  // NaN and infinities land in a border cell rather than past the grid.
  const int ix = std::isfinite(fx) ? int(std::clamp(std::floor(fx), 0.0, double(nx - 1))) : 0;
  const int iy = std::isfinite(fy) ? int(std::clamp(std::floor(fy), 0.0, double(ny - 1))) : 0;
  return iy * nx + ix;
}

TileGridXY makeTileGrid(glm::dvec2 lo, glm::dvec2 hi, std::size_t triangles, int perTile) {
  TileGridXY g;
  if (!(std::isfinite(lo.x) && std::isfinite(lo.y) && std::isfinite(hi.x) && std::isfinite(hi.y)) || hi.x < lo.x ||
      hi.y < lo.y)
    return g;
  const glm::dvec2 size = glm::max(hi - lo, glm::dvec2(1e-9));
  const double cells = std::clamp(double(triangles) / std::max(1, perTile), 1.0, 256.0 * 256.0);
  g.cell = std::sqrt(size.x * size.y / cells);
  g.cell = std::max({g.cell, size.x / 256.0, size.y / 256.0});
  g.nx = std::clamp(int(std::ceil(size.x / g.cell)), 1, 256);
  g.ny = std::clamp(int(std::ceil(size.y / g.cell)), 1, 256);
  g.origin = lo;
  return g;
}

void appendTiledLayer(int layer, const std::vector<glm::dvec3>& positions, const std::vector<glm::uvec3>& triangles,
                      const std::vector<std::uint32_t>& tags, std::uint32_t base, const TileGridXY& grid,
                      std::vector<std::uint32_t>& indices, std::vector<GeometryTile>& tiles,
                      const std::vector<std::uint32_t>& tileOfTag) {
  const std::size_t n = triangles.size();
  if (n == 0) return;
  const bool tagged = tags.size() == n;
  // A tag's cell: the centre of the box of its triangles (a building is one tag).
  std::unordered_map<std::uint32_t, std::pair<glm::dvec2, glm::dvec2>> tagBox;
  if (tagged) {
    for (std::size_t t = 0; t < n; ++t) {
      auto [it, fresh] = tagBox.try_emplace(tags[t], glm::dvec2(INFINITY), glm::dvec2(-INFINITY));
      for (int k = 0; k < 3; ++k) {
        const glm::dvec2 p(positions[triangles[t][k]]);
        it->second.first = glm::min(it->second.first, p);
        it->second.second = glm::max(it->second.second, p);
      }
    }
  }
  std::vector<int> cell(n);
  // Tiles given by the source come after the grid's cells (they are never mixed in one layer
  // unless some tag has none).
  const int gridCells = grid.nx * grid.ny;
  for (std::size_t t = 0; t < n; ++t) {
    if (tagged && tags[t] < tileOfTag.size()) {
      cell[t] = gridCells + int(tileOfTag[tags[t]]);
      continue;
    }
    glm::dvec2 c;
    if (tagged) {
      const auto& box = tagBox.at(tags[t]);
      c = 0.5 * (box.first + box.second);
    } else {
      const glm::uvec3& tri = triangles[t];
      c = (glm::dvec2(positions[tri.x]) + glm::dvec2(positions[tri.y]) + glm::dvec2(positions[tri.z])) / 3.0;
    }
    cell[t] = grid.cellOf(c);
  }
  // Stable: within a tile the triangles keep the mesh's order.
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return cell[a] < cell[b]; });
  for (std::size_t i = 0; i < n;) {
    const int c = cell[order[i]];
    GeometryTile tile;
    tile.layer = layer;
    tile.range.first = int(indices.size());
    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    for (; i < n && cell[order[i]] == c; ++i) {
      const glm::uvec3& tri = triangles[order[i]];
      for (int k = 0; k < 3; ++k) {
        const glm::dvec3& p = positions[tri[k]];
        // A non-finite vertex is drawn (the GPU clips it) but does not blow the box up.
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) {
          lo = glm::min(lo, p);
          hi = glm::max(hi, p);
        }
        indices.push_back(tri[k] + base);
      }
    }
    tile.range.count = int(indices.size()) - tile.range.first;
    if (lo.x > hi.x) lo = hi = glm::dvec3(0.0);
    // Rounded outwards so that the float box still holds every double vertex.
    tile.lo = glm::vec3(lo);
    tile.hi = glm::vec3(hi);
    for (int a = 0; a < 3; ++a) {
      if (double(tile.lo[a]) > lo[a]) tile.lo[a] = std::nextafter(tile.lo[a], -INFINITY);
      if (double(tile.hi[a]) < hi[a]) tile.hi[a] = std::nextafter(tile.hi[a], INFINITY);
    }
    tiles.push_back(tile);
  }
}

bool boxMayBeVisible(const glm::dmat4& m, const glm::vec3& lo, const glm::vec3& hi) {
  // For each plane, whether every corner is outside it: x > w, x < -w, y..., z...
  int outside[6] = {0, 0, 0, 0, 0, 0};
  for (int c = 0; c < 8; ++c) {
    const glm::dvec4 p = m * glm::dvec4(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z, 1.0);
    outside[0] += p.x > p.w;
    outside[1] += p.x < -p.w;
    outside[2] += p.y > p.w;
    outside[3] += p.y < -p.w;
    outside[4] += p.z > p.w;
    outside[5] += p.z < -p.w;
  }
  for (int k = 0; k < 6; ++k)
    if (outside[k] == 8) return false;
  return true;
}

std::vector<DrawRange> visibleRanges(const std::vector<GeometryTile>& tiles, const std::array<bool, kLayerCount>& layers,
                                     const glm::dmat4& clipFromRender, bool cull, int* tilesDrawn) {
  std::vector<DrawRange> out;
  int drawn = 0;
  for (const GeometryTile& t : tiles) {
    if (t.range.count == 0 || !layers[size_t(t.layer)]) continue;
    if (cull && !boxMayBeVisible(clipFromRender, t.lo, t.hi)) continue;
    ++drawn;
    if (!out.empty() && out.back().first + out.back().count == t.range.first)
      out.back().count += t.range.count;
    else
      out.push_back(t.range);
  }
  if (tilesDrawn) *tilesDrawn = drawn;
  return out;
}

}  // namespace hv::render
