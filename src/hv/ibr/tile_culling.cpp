#include "hv/ibr/tile_culling.h"

#include <algorithm>
#include <limits>

namespace hv::ibr {

int TileLists::maxCount() const {
  size_t m = 0;
  for (const auto& l : lists) m = std::max(m, l.size());
  return int(m);
}

double TileLists::meanCount() const {
  if (lists.empty()) return 0.0;
  size_t s = 0;
  for (const auto& l : lists) s += l.size();
  return double(s) / double(lists.size());
}

std::vector<glm::dvec3> tileSlabCorners(const Camera& view, const glm::dvec3& origin, const TileGrid& g, int tx,
                                        int ty, const TileDepth& d) {
  const glm::dvec3 c = view.center - origin;
  const glm::dmat3 dirFromPix = glm::transpose(view.camFromWorld) * view.camFromPix();
  const glm::dvec2 size = g.rect.pxMax - g.rect.pxMin;
  std::vector<glm::dvec3> out;
  for (int corner = 0; corner < 4; ++corner) {
    const glm::dvec2 texel(std::min((tx + (corner & 1)) * g.tileSize, g.depthSize.x),
                           std::min((ty + (corner >> 1)) * g.tileSize, g.depthSize.y));
    const glm::dvec2 px = g.rect.pxMin + texel / glm::dvec2(g.depthSize) * size;
    const glm::dvec3 dir = dirFromPix * glm::dvec3(px, 1.0);  // camera z = 1: depth scales it
    out.push_back(c + d.zMin * dir);
    out.push_back(c + d.zMax * dir);
  }
  return out;
}

TileLists buildTileLists(const Camera& view, const glm::dvec3& origin, const TileGrid& g,
                         const std::vector<TileDepth>& depth, const std::vector<ImageParams>& images) {
  TileLists out;
  out.tilesX = g.tilesX();
  out.tilesY = g.tilesY();
  out.lists.resize(size_t(out.tilesX) * out.tilesY);
  for (int ty = 0; ty < out.tilesY; ++ty) {
    for (int tx = 0; tx < out.tilesX; ++tx) {
      const size_t t = size_t(ty) * out.tilesX + tx;
      if (depth[t].empty) continue;
      const auto corners = tileSlabCorners(view, origin, g, tx, ty, depth[t]);
      for (size_t i = 0; i < images.size(); ++i) {
        const ImageParams& im = images[i];
        glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
        bool behind = false;
        for (const auto& p : corners) {
          const glm::dvec3 ph = im.pixFromWorld * (p - im.centerRender);
          if (ph.z <= 0.0) {
            behind = true;
            break;
          }
          const glm::dvec2 px = glm::dvec2(ph) / ph.z;
          lo = glm::min(lo, px);
          hi = glm::max(hi, px);
        }
        const bool overlaps = behind || (lo.x <= im.depth.pxMax.x && hi.x >= im.depth.pxMin.x &&
                                         lo.y <= im.depth.pxMax.y && hi.y >= im.depth.pxMin.y);
        if (overlaps) out.lists[t].push_back(std::uint16_t(i));
      }
    }
  }
  return out;
}

std::vector<TileDepth> decodeTileDepth(const std::vector<std::uint8_t>& rgba, const TileGrid& g) {
  const size_t n = size_t(g.tilesX()) * g.tilesY();
  std::vector<TileDepth> out(n);
  for (size_t t = 0; t < n; ++t) {
    const std::uint8_t* v = &rgba[4 * t];
    const double dMin = (v[0] * 256 + v[1]) / 65535.0, dMax = (v[2] * 256 + v[3]) / 65535.0;
    if (dMin > dMax) continue;  // the shader writes min > max for a tile with no surface
    out[t].empty = false;
    out[t].zMin = g.rect.near + dMin * (g.rect.far - g.rect.near);
    out[t].zMax = g.rect.near + dMax * (g.rect.far - g.rect.near);
  }
  return out;
}

}  // namespace hv::ibr
