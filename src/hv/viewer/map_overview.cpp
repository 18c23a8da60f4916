#include "hv/viewer/map_overview.h"

#include "hv/scene/orthophoto.h"
#include "hv/scene/robust_extent.h"
#include "hv/scene/scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

namespace hv::viewer {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

glm::dvec2 unitOr0(const glm::dvec2& v) {
  const double l = glm::length(v);
  return l > 1e-9 ? v / l : glm::dvec2(0.0);
}
}  // namespace

glm::dvec2 MapFrame::toPixel(const glm::dvec2& p) const {
  return offset + pixelsPerUnit * glm::dvec2(p.x - box.lo.x, box.hi.y - p.y);
}
glm::dvec2 MapFrame::toPlane(const glm::dvec2& px) const {
  return {box.lo.x + (px.x - offset.x) / pixelsPerUnit, box.hi.y - (px.y - offset.y) / pixelsPerUnit};
}

MapFrame fitMap(const PlaneBox& box, int width, int height) {
  MapFrame f;
  f.box = box;
  f.width = std::max(width, 1);
  f.height = std::max(height, 1);
  const glm::dvec2 size = glm::max(box.size(), glm::dvec2(1e-9));
  f.pixelsPerUnit = std::min(f.width / size.x, f.height / size.y);
  f.offset = 0.5 * (glm::dvec2(f.width, f.height) - f.pixelsPerUnit * size);
  return f;
}

MapFrame zoomedMap(const PlaneBox& box, int width, int height, const MapZoom& zoom) {
  MapFrame f = fitMap(box, width, height);
  f.pixelsPerUnit *= zoom.zoom;
  const glm::dvec2 c = zoom.center.value_or(0.5 * (box.lo + box.hi));
  // toPixel(c) = offset + ppu (c.x - lo.x, hi.y - c.y) = (width, height) / 2.
  f.offset = 0.5 * glm::dvec2(f.width, f.height) - f.pixelsPerUnit * glm::dvec2(c.x - box.lo.x, box.hi.y - c.y);
  return f;
}

MapZoom clampZoom(const PlaneBox& box, int width, int height, MapZoom zoom, const MapZoomLimits& limits) {
  const double z = std::isfinite(zoom.zoom) ? zoom.zoom : 1.0;
  zoom.zoom = std::clamp(z, 1.0, std::max(limits.maxZoom, 1.0));
  const glm::dvec2 mid = 0.5 * (box.lo + box.hi);
  if (zoom.zoom == 1.0 || !zoom.center) {
    zoom.center.reset();  // the fitted layout
    if (zoom.zoom == 1.0) return zoom;
  }
  const MapFrame f = zoomedMap(box, width, height, zoom);
  const glm::dvec2 halfSpan = 0.5 * glm::dvec2(f.width, f.height) / f.pixelsPerUnit;  // plane units
  glm::dvec2 c = zoom.center.value_or(mid);
  for (int a = 0; a < 2; ++a) {
    if (!std::isfinite(c[a])) c[a] = mid[a];
    c[a] =
        box.size()[a] > 2.0 * halfSpan[a] ? std::clamp(c[a], box.lo[a] + halfSpan[a], box.hi[a] - halfSpan[a]) : mid[a];
  }
  zoom.center = c;
  return zoom;
}

MapZoom zoomAbout(const PlaneBox& box, int width, int height, const MapZoom& zoom, const glm::dvec2& pixel,
                  double factor, const MapZoomLimits& limits) {
  if (!(factor > 0.0) || !std::isfinite(factor)) return zoom;
  const MapFrame before = zoomedMap(box, width, height, zoom);
  const glm::dvec2 under = before.toPlane(pixel);
  MapZoom z = zoom;
  z.zoom = std::clamp(zoom.zoom * factor, 1.0, std::max(limits.maxZoom, 1.0));
  // The centre c with toPixel(under) = pixel: c = under - (pixel - mid px) (1, -1) / ppu.
  const double ppu = before.pixelsPerUnit / zoom.zoom * z.zoom;
  const glm::dvec2 d = (pixel - 0.5 * glm::dvec2(before.width, before.height)) / ppu;
  z.center = under - glm::dvec2(d.x, -d.y);
  return clampZoom(box, width, height, z, limits);
}

MapZoom panBy(const PlaneBox& box, int width, int height, const MapZoom& zoom, const glm::dvec2& deltaPx,
              const MapZoomLimits& limits) {
  const MapFrame f = zoomedMap(box, width, height, zoom);
  const glm::dvec2 c = f.toPlane(0.5 * glm::dvec2(f.width, f.height) - deltaPx);
  MapZoom z = zoom;
  z.center = c;
  return clampZoom(box, width, height, z, limits);
}

glm::dvec2 HeightGrid::cellSize() const {
  return cols > 0 && rows > 0 ? box.size() / glm::dvec2(cols, rows) : glm::dvec2(1.0);
}

std::optional<double> HeightGrid::heightAt(const glm::dvec2& p) const {
  if (empty() || p.x < box.lo.x || p.x > box.hi.x || p.y < box.lo.y || p.y > box.hi.y) return std::nullopt;
  const glm::dvec2 cell = cellSize();
  const double fx = (p.x - box.lo.x) / cell.x - 0.5, fy = (box.hi.y - p.y) / cell.y - 0.5;
  const int i0 = int(std::floor(fx)), j0 = int(std::floor(fy));
  const double tx = fx - i0, ty = fy - j0;
  double sum = 0.0, weight = 0.0;
  for (int dj = 0; dj < 2; ++dj)
    for (int di = 0; di < 2; ++di) {
      const int i = std::clamp(i0 + di, 0, cols - 1), j = std::clamp(j0 + dj, 0, rows - 1);
      const double h = at(i, j);
      const double w = (di ? tx : 1.0 - tx) * (dj ? ty : 1.0 - ty);
      if (std::isnan(h) || w <= 0.0) continue;
      sum += w * h;
      weight += w;
    }
  if (weight > 0.0) return sum / weight;
  // Only corners without terrain carry weight: the cell under the point itself, if it has some.
  const int i = std::clamp(int(std::floor(fx + 0.5)), 0, cols - 1),
            j = std::clamp(int(std::floor(fy + 0.5)), 0, rows - 1);
  return std::isnan(at(i, j)) ? std::nullopt : std::optional<double>(at(i, j));
}

HeightGrid rasterizeHeights(const std::vector<glm::dvec3>& pos, const std::vector<glm::uvec3>& triangles,
                            const PlaneBox& box, int cols, int rows) {
  HeightGrid g;
  g.box = box;
  g.cols = std::max(cols, 1);
  g.rows = std::max(rows, 1);
  g.heights.assign(std::size_t(g.cols) * g.rows, kNaN);
  const glm::dvec2 cell = g.cellSize();
  for (const glm::uvec3& t : triangles) {
    if (t.x >= pos.size() || t.y >= pos.size() || t.z >= pos.size()) continue;
    const glm::dvec3 a = pos[t.x], b = pos[t.y], c = pos[t.z];
    const double det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    if (!std::isfinite(det) || std::abs(det) < 1e-12) continue;  // vertical or degenerate in the plane
    const double xlo = std::min({a.x, b.x, c.x}), xhi = std::max({a.x, b.x, c.x});
    const double ylo = std::min({a.y, b.y, c.y}), yhi = std::max({a.y, b.y, c.y});
    // Cells whose centres may lie in the triangle: i with lo.x + (i + 0.5) cell.x in [xlo, xhi].
    const int i0 = std::max(0, int(std::ceil((xlo - box.lo.x) / cell.x - 0.5)));
    const int i1 = std::min(g.cols - 1, int(std::floor((xhi - box.lo.x) / cell.x - 0.5)));
    const int j0 = std::max(0, int(std::ceil((box.hi.y - yhi) / cell.y - 0.5)));
    const int j1 = std::min(g.rows - 1, int(std::floor((box.hi.y - ylo) / cell.y - 0.5)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const double px = box.lo.x + (i + 0.5) * cell.x, py = box.hi.y - (j + 0.5) * cell.y;
        const double u = ((px - a.x) * (c.y - a.y) - (c.x - a.x) * (py - a.y)) / det;
        const double v = ((b.x - a.x) * (py - a.y) - (px - a.x) * (b.y - a.y)) / det;
        const double eps = 1e-9;
        if (u < -eps || v < -eps || u + v > 1.0 + eps) continue;
        const double h = a.z + u * (b.z - a.z) + v * (c.z - a.z);
        double& cellH = g.heights[std::size_t(j) * g.cols + i];
        if (std::isnan(cellH) || h > cellH) cellH = h;
      }
  }
  return g;
}

Image8 hillshade(const HeightGrid& g, double azimuthDeg, double altitudeDeg, double zFactor) {
  Image8 out(g.cols, g.rows, 2, 0);
  if (g.empty()) return out;
  const glm::dvec2 cell = g.cellSize();
  const double az = glm::radians(azimuthDeg), alt = glm::radians(altitudeDeg);
  // The light's direction in (east, north, up): azimuth clockwise from north.
  const glm::dvec3 light(std::sin(az) * std::cos(alt), std::cos(az) * std::cos(alt), std::sin(alt));
  const auto valid = [&](int i, int j) {
    return i >= 0 && j >= 0 && i < g.cols && j < g.rows && !std::isnan(g.at(i, j));
  };
  // The derivative along one axis from the neighbours that have terrain (central, else one-sided).
  const auto derivative = [&](int i, int j, int di, int dj, double step) {
    const bool f = valid(i + di, j + dj), b = valid(i - di, j - dj);
    if (f && b) return (g.at(i + di, j + dj) - g.at(i - di, j - dj)) / (2.0 * step);
    if (f) return (g.at(i + di, j + dj) - g.at(i, j)) / step;
    if (b) return (g.at(i, j) - g.at(i - di, j - dj)) / step;
    return 0.0;
  };
  for (int j = 0; j < g.rows; ++j)
    for (int i = 0; i < g.cols; ++i) {
      if (!valid(i, j)) continue;
      const double dzde = zFactor * derivative(i, j, 1, 0, cell.x);
      const double dzdn = zFactor * derivative(i, j, 0, -1, cell.y);  // north is the row above
      const glm::dvec3 normal = glm::normalize(glm::dvec3(-dzde, -dzdn, 1.0));
      const double shade = std::max(0.0, glm::dot(normal, light));
      out.at(i, j, 0) = std::uint8_t(std::lround(255.0 * shade));
      out.at(i, j, 1) = 255;
    }
  return out;
}

glm::dvec3 MapOverview::groundAt(const glm::dvec2& p) const {
  const double h = terrain.heightAt(p).value_or(groundLevel);
  return p.x * axes.east + p.y * axes.north + h * axes.up;
}

MapOverview mapOverview(const Scene& scene, const std::vector<bool>& dated, int maxRaster) {
  MapOverview m;
  m.axes = upFrame(scene.up);
  const RobustExtent robust = robustExtent(scene);
  const Aabb& g = !robust.geometry.empty() ? robust.geometry : robust.bounds;
  if (!g.empty()) {
    glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    double low = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 corner((k & 1) ? g.hi.x : g.lo.x, (k & 2) ? g.hi.y : g.lo.y, (k & 4) ? g.hi.z : g.lo.z);
      lo = glm::min(lo, m.toPlane(corner));
      hi = glm::max(hi, m.toPlane(corner));
      low = std::min(low, glm::dot(corner, m.axes.up));
    }
    const double margin = std::max(0.05 * std::max(hi.x - lo.x, hi.y - lo.y), 1.0);
    m.extent = {lo - margin, hi + margin};
    m.groundLevel = low;
  } else {
    m.extent = {glm::dvec2(-1.0), glm::dvec2(1.0)};
  }

  // Footprints: upward-facing building triangles; their edges that no other upward-facing
  // triangle of the same building shares (endpoints compared at 0.1 mm, so meshes with
  // duplicated vertices still join) are the outlines.
  const Mesh& b = scene.buildings;
  using Key = std::tuple<std::uint32_t, std::int64_t, std::int64_t, std::int64_t, std::int64_t>;
  std::map<Key, std::pair<int, std::array<glm::dvec2, 2>>> edges;
  const auto quantize = [&](const glm::dvec2& p) {
    return std::pair<std::int64_t, std::int64_t>(std::llround((p.x - m.extent.lo.x) * 1e4),
                                                 std::llround((p.y - m.extent.lo.y) * 1e4));
  };
  for (std::size_t t = 0; t < b.triangles.size(); ++t) {
    const glm::uvec3 tri = b.triangles[t];
    if (tri.x >= b.positions.size() || tri.y >= b.positions.size() || tri.z >= b.positions.size()) continue;
    const glm::dvec3 a = b.positions[tri.x], bb = b.positions[tri.y], c = b.positions[tri.z];
    const glm::dvec3 n = glm::cross(bb - a, c - a);
    const double len = glm::length(n);
    if (!(len > 0.0) || glm::dot(n, m.axes.up) < 0.5 * len) continue;  // walls, floors, slivers
    const std::array<glm::dvec2, 3> p{m.toPlane(a), m.toPlane(bb), m.toPlane(c)};
    m.footprintTriangles.insert(m.footprintTriangles.end(), p.begin(), p.end());
    const std::uint32_t tag = t < b.triangleTags.size() ? b.triangleTags[t] : 0u;
    for (int e = 0; e < 3; ++e) {
      auto qa = quantize(p[e]), qb = quantize(p[(e + 1) % 3]);
      if (qb < qa) std::swap(qa, qb);
      auto& entry = edges[Key{tag, qa.first, qa.second, qb.first, qb.second}];
      ++entry.first;
      entry.second = {p[e], p[(e + 1) % 3]};
    }
  }
  for (const auto& [key, entry] : edges)
    if (entry.first == 1) {
      m.outlineSegments.push_back(entry.second[0]);
      m.outlineSegments.push_back(entry.second[1]);
    }

  // The terrain's hillshade over the extent, square cells.
  if (!scene.terrain.empty()) {
    const glm::dvec2 size = m.extent.size();
    const double cell = std::max(size.x, size.y) / std::max(maxRaster, 1);
    const int cols = std::max(1, int(std::ceil(size.x / cell - 1e-9)));
    const int rows = std::max(1, int(std::ceil(size.y / cell - 1e-9)));
    const PlaneBox box{m.extent.lo, m.extent.lo + glm::dvec2(cols * cell, rows * cell)};
    std::vector<glm::dvec3> planar;
    planar.reserve(scene.terrain.positions.size());
    for (const glm::dvec3& p : scene.terrain.positions) planar.emplace_back(m.toPlane(p), glm::dot(p, m.axes.up));
    m.terrain = rasterizeHeights(planar, scene.terrain.triangles, box, cols, rows);
    m.shade = hillshade(m.terrain);
  }

  for (std::size_t i = 0; i < scene.photos.size(); ++i) {
    const Camera& c = scene.photos[i].camera;
    MapDot d;
    d.photo = int(i);
    d.at = m.toPlane(c.center);
    d.direction = unitOr0(m.toPlane(forwardOf(c)));
    d.dated = i < dated.size() && dated[i];
    m.dots.push_back(d);
  }
  return m;
}

MapView mapView(const MapOverview& map, const Camera& view) {
  return {map.toPlane(view.center), unitOr0(map.toPlane(forwardOf(view)))};
}

glm::dvec2 pixelDirection(const glm::dvec2& d) { return unitOr0({d.x, -d.y}); }

MapClick clickMap(const MapOverview& map, const MapFrame& frame, const glm::dvec2& pixel, double radiusPx) {
  MapClick click;
  double best = radiusPx;
  for (const MapDot& d : map.dots) {
    const double dist = glm::distance(frame.toPixel(d.at), pixel);
    if (dist <= best) {
      best = dist;
      click.photo = d.photo;
    }
  }
  if (click.photo < 0) click.ground = map.groundAt(frame.toPlane(pixel));
  return click;
}

Camera viewOverGround(const Camera& view, const glm::dvec3& ground, const glm::dvec3& up, double height) {
  Camera c = view;
  c.center = ground + glm::normalize(up) * height;
  return c;
}

std::optional<PlaneBox> orthophotoOnMap(const MapOverview& map, const Orthophoto& orthophoto,
                                        const glm::dvec3& origin) {
  if (orthophoto.empty()) return std::nullopt;
  if (glm::length(map.axes.east - glm::dvec3(1, 0, 0)) > 1e-9 ||
      glm::length(map.axes.north - glm::dvec3(0, 1, 0)) > 1e-9)
    return std::nullopt;
  return PlaneBox{{orthophoto.minX - origin.x, orthophoto.minY - origin.y},
                  {orthophoto.maxX - origin.x, orthophoto.maxY - origin.y}};
}

}  // namespace hv::viewer
