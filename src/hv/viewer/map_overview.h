// The map: a 2D overview of a scene in its ground plane — the extent of the geometry, the
// buildings' footprints, a hillshade of the terrain, every photograph as a dot with its viewing
// direction, the view's position and heading — and a click on it turned into where to go. Plain
// data and arithmetic; the desktop viewer's map panel and the page's map only draw it.
//
// Conventions: the ground plane is the plane orthogonal to the scene's up, with the axes of
// hv/viewer/navigation.h's UpFrame: plane coordinates (e, n) = (p . east, p . north), height
// h = p . up (for a scene with a CRS or up = z: e = x, n = y, h = z). Map pixels as
// hv/camera/camera.h's (origin at the top-left corner, x right, y down): north is up on the map.
#pragma once

#include "hv/image/image.h"
#include "hv/viewer/navigation.h"

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

namespace hv {
struct Scene;       // hv/scene/scene.h
struct Orthophoto;  // hv/scene/orthophoto.h
}  // namespace hv

namespace hv::viewer {

// A rectangle of the ground plane (plane coordinates), lo <= hi.
struct PlaneBox {
  glm::dvec2 lo{0.0}, hi{0.0};
  glm::dvec2 size() const { return hi - lo; }
};

// The rectangle `box` shown in a map of width x height pixels: one scale for both axes (the
// larger of the box's sides fits), centred; north up.
struct MapFrame {
  PlaneBox box;
  int width = 0, height = 0;
  double pixelsPerUnit = 1.0;
  glm::dvec2 offset{0.0};  // pixel of the plane point box.lo's (e, n) = (lo.x, hi.y) corner: top-left

  glm::dvec2 toPixel(const glm::dvec2& plane) const;
  glm::dvec2 toPlane(const glm::dvec2& pixel) const;
};
MapFrame fitMap(const PlaneBox& box, int width, int height);

// The map zoomed and panned: `zoom` times fitMap's scale (1: the whole extent), `center` the plane
// point at the map's centre. Kept in plane units, so a resized map keeps showing the same place.
struct MapZoom {
  double zoom = 1.0;
  std::optional<glm::dvec2> center;  // none: the box's centre
  bool whole() const { return zoom == 1.0 && !center; }
};
// The frame of `zoom` over `box` in a width x height map: pixelsPerUnit = zoom * fitMap's, the
// centre's plane point at pixel (width / 2, height / 2).
MapFrame zoomedMap(const PlaneBox& box, int width, int height, const MapZoom& zoom);
// The limits a zoom is kept within: zoom in [1, maxZoom]; along each axis the centre such that the
// map shows no more than the box where the box is wider than the map (the view stays on it), else
// the box's centre (the fitted, centred layout).
struct MapZoomLimits {
  double maxZoom = 64.0;
};
MapZoom clampZoom(const PlaneBox& box, int width, int height, MapZoom zoom, const MapZoomLimits& limits = {});
// Zooming by `factor` about map pixel `pixel`: the plane point under it stays under it (unless
// the limits move it: at zoom 1 the map is the fitted one).
MapZoom zoomAbout(const PlaneBox& box, int width, int height, const MapZoom& zoom, const glm::dvec2& pixel,
                  double factor, const MapZoomLimits& limits = {});
// Panning by `deltaPx` map pixels (a drag): the plane point under the pointer follows it.
MapZoom panBy(const PlaneBox& box, int width, int height, const MapZoom& zoom, const glm::dvec2& deltaPx,
              const MapZoomLimits& limits = {});
// The mouse wheel's zoom: a factor of 2^(1/4) a notch (four notches double the scale).
inline double wheelZoomFactor(double notches) { return std::exp2(0.25 * notches); }

// A height field over a plane box: `cols` x `rows` cells, cell (i, j)'s centre at
// lo + ((i + 0.5) * cell.x, (rows - j - 0.5) * cell.y) (row 0 the northern edge, as an image);
// NaN where no terrain triangle covers the centre.
struct HeightGrid {
  PlaneBox box;
  int cols = 0, rows = 0;
  std::vector<double> heights;  // row-major, rows * cols

  bool empty() const { return heights.empty(); }
  double at(int i, int j) const { return heights[std::size_t(j) * cols + i]; }
  glm::dvec2 cellSize() const;
  // The height at a plane point, bilinear between cell centres (nearest valid cell at the edges);
  // none outside the box or where no terrain is.
  std::optional<double> heightAt(const glm::dvec2& plane) const;
};

// Rasterises the triangles of a mesh's heights (positions already in plane coordinates and
// heights: x = e, y = n, z = h) at the cell centres; where triangles overlap, the highest.
HeightGrid rasterizeHeights(const std::vector<glm::dvec3>& planePositions, const std::vector<glm::uvec3>& triangles,
                            const PlaneBox& box, int cols, int rows);

// The standard hillshade (Burrough & McDonnell; as GDAL's gdaldem hillshade with its defaults):
// 255 * max(0, cos(zenith) cos(slope) + sin(zenith) sin(slope) cos(azimuth - aspect)), i.e. the
// cosine between the surface normal and the light coming from `azimuthDeg` (clockwise from north)
// at `altitudeDeg` above the horizon. Slopes from central differences (one-sided at the edges and
// beside cells without terrain), `zFactor` scaling the heights. A grey and alpha image of the
// grid's size: alpha 255 where there is terrain, 0 elsewhere.
Image8 hillshade(const HeightGrid& grid, double azimuthDeg = 315.0, double altitudeDeg = 45.0, double zFactor = 1.0);

// A photograph on the map.
struct MapDot {
  int photo = -1;             // index into scene.photos
  glm::dvec2 at{0.0};         // its camera centre in the plane
  glm::dvec2 direction{0.0};  // its optical axis projected on the plane, unit (0 when looking straight up or down)
  bool dated = false;         // a date parseDate accepts (viewer/timeline.h's PhotoDates)
};

struct MapOverview {
  UpFrame axes;     // the plane's axes (navigation.h)
  PlaneBox extent;  // the geometry's robust extent (hv/scene/robust_extent.h), with a margin
  // The buildings' footprints: the edges of their upward-facing triangles (roofs, for LOD1
  // prisms the footprint itself) that no other upward-facing triangle of the same building
  // shares, as segments in the plane (a, b pairs), and the triangles themselves (filled).
  std::vector<glm::dvec2> outlineSegments;
  std::vector<glm::dvec2> footprintTriangles;
  HeightGrid terrain;  // the terrain's heights (empty: no terrain)
  Image8 shade;        // hillshade(terrain), grey + alpha (empty: no terrain)
  std::vector<MapDot> dots;
  double groundLevel = 0.0;  // the geometry's lowest height: the ground where there is no terrain

  glm::dvec2 toPlane(const glm::dvec3& world) const {
    return {glm::dot(world, axes.east), glm::dot(world, axes.north)};
  }
  // The world point on the ground at a plane point: the terrain's height there, else groundLevel.
  glm::dvec3 groundAt(const glm::dvec2& plane) const;
};

// The overview of `scene`. `dated[i]`: photograph i has a date (PhotoDates::when[i]); empty: all
// undated. `maxRaster`: the hillshade's longer side in cells.
MapOverview mapOverview(const Scene& scene, const std::vector<bool>& dated, int maxRaster = 256);

// The rectangle an orthophoto (scene.json "orthophoto") covers on the map, in plane coordinates,
// the image's row 0 along its northern edge (hi.y); `origin` the scene's render origin. Only when
// the map's plane is the scene frame's x, y (east (1, 0, 0), north (0, 1, 0): a scene whose up is
// +z, as every scene with a CRS); none otherwise, and none for an empty orthophoto.
std::optional<PlaneBox> orthophotoOnMap(const MapOverview& map, const Orthophoto& orthophoto, const glm::dvec3& origin);

// The view on the map: its centre and the heading of its viewing direction (a unit vector in the
// plane; 0 when looking straight up or down).
struct MapView {
  glm::dvec2 at{0.0};
  glm::dvec2 direction{0.0};
};
MapView mapView(const MapOverview& map, const Camera& view);
// A direction in the plane to map pixels (y down), unit length (0 stays 0).
glm::dvec2 pixelDirection(const glm::dvec2& planeDirection);

// A click on the map at `pixel`: the nearest photograph whose dot lies within `radiusPx` (its
// index), else the ground there.
struct MapClick {
  int photo = -1;
  glm::dvec3 ground{0.0};  // world point on the ground (valid when photo < 0)
};
MapClick clickMap(const MapOverview& map, const MapFrame& frame, const glm::dvec2& pixel, double radiusPx = 6.0);

// Going to a ground point: the view's rotation and intrinsics kept (so its heading), its centre
// `height` above `ground` along `up`.
Camera viewOverGround(const Camera& view, const glm::dvec3& ground, const glm::dvec3& up, double height);

}  // namespace hv::viewer
