// The map's arithmetic (viewer/map_overview.h): the frame's pixels, the height raster, the
// hillshade against the textbook formula written with the compass aspect (Burrough & McDonnell:
// 255 (cos Z cos S + sin Z sin S cos(A - aspect))), the footprints of a prism, the dots and clicks.
#include "hv/viewer/map_overview.h"

#include "hv/scene/orthophoto.h"
#include "hv/scene/scene.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv::viewer {
namespace {

TEST(MapOverview, FrameFitsTheBoxNorthUp) {
  // 100 x 50 units in 200 x 200 pixels: 2 pixels a unit, letterboxed 50 pixels top and bottom.
  const MapFrame f = fitMap({{0, 0}, {100, 50}}, 200, 200);
  EXPECT_DOUBLE_EQ(f.pixelsPerUnit, 2.0);
  const glm::dvec2 nw = f.toPixel({0, 50}), se = f.toPixel({100, 0});
  EXPECT_NEAR(nw.x, 0.0, 1e-12);
  EXPECT_NEAR(nw.y, 50.0, 1e-12);
  EXPECT_NEAR(se.x, 200.0, 1e-12);
  EXPECT_NEAR(se.y, 150.0, 1e-12);
  const glm::dvec2 back = f.toPlane(f.toPixel({12.5, 33.0}));
  EXPECT_NEAR(back.x, 12.5, 1e-12);
  EXPECT_NEAR(back.y, 33.0, 1e-12);
}

// A plane h = a e + b n + c over [0, 10]^2 as two triangles.
HeightGrid planeGrid(double a, double b, double c, int cells) {
  const auto h = [&](double e, double n) { return glm::dvec3(e, n, a * e + b * n + c); };
  const std::vector<glm::dvec3> pos{h(0, 0), h(10, 0), h(10, 10), h(0, 10)};
  const std::vector<glm::uvec3> tris{{0, 1, 2}, {0, 2, 3}};
  return rasterizeHeights(pos, tris, {{0, 0}, {10, 10}}, cells, cells);
}

TEST(MapOverview, RasterisesHeightsAtCellCentres) {
  const HeightGrid g = planeGrid(2.0, 3.0, 1.0, 5);  // 2-unit cells
  ASSERT_EQ(g.heights.size(), 25u);
  // Cell (1, 0): centre (3, 9) (row 0 the northern edge): 2*3 + 3*9 + 1 = 34.
  EXPECT_NEAR(g.at(1, 0), 34.0, 1e-9);
  // Cell (4, 4): centre (9, 1): 18 + 3 + 1 = 22.
  EXPECT_NEAR(g.at(4, 4), 22.0, 1e-9);
  // Bilinear between centres is exact on a plane.
  EXPECT_NEAR(*g.heightAt({4.2, 6.7}), 2 * 4.2 + 3 * 6.7 + 1, 1e-9);
  EXPECT_FALSE(g.heightAt({11.0, 5.0}));
}

double textbookHillshade(double slopeDeg, double aspectDeg) {
  const double zenith = glm::radians(90.0 - 45.0), azimuth = glm::radians(315.0);
  const double s = glm::radians(slopeDeg), asp = glm::radians(aspectDeg);
  return 255.0 *
         std::max(0.0, std::cos(zenith) * std::cos(s) + std::sin(zenith) * std::sin(s) * std::cos(azimuth - asp));
}

TEST(MapOverview, HillshadeOfPlanesOfKnownSlope) {
  // Rising to the east at 45°: the slope faces west (aspect 270°): 255 (0.5 + 0.5 cos 45°) = 217.7.
  Image8 s = hillshade(planeGrid(1.0, 0.0, 0.0, 8));
  EXPECT_NEAR(s.at(3, 3, 0), textbookHillshade(45.0, 270.0), 0.5);
  EXPECT_EQ(s.at(0, 0, 0), s.at(3, 3, 0));  // one-sided at the edge: the same plane
  EXPECT_EQ(s.at(3, 3, 1), 255);
  // Rising to the north at 45°: it faces south (180°), away from the north-west light: 37.3.
  s = hillshade(planeGrid(0.0, 1.0, 0.0, 8));
  EXPECT_NEAR(s.at(4, 4, 0), textbookHillshade(45.0, 180.0), 0.5);
  // Flat: cos(zenith) = 0.707: 180.3.
  s = hillshade(planeGrid(0.0, 0.0, 7.0, 8));
  EXPECT_NEAR(s.at(2, 5, 0), textbookHillshade(0.0, 0.0), 0.5);
  // A gentle slope to the north-west (rising south-east), facing the light: slope atan(0.5 sqrt 2).
  s = hillshade(planeGrid(0.5, -0.5, 0.0, 8));
  EXPECT_NEAR(s.at(4, 4, 0), textbookHillshade(glm::degrees(std::atan(0.5 * std::sqrt(2.0))), 315.0), 0.5);
}

TEST(MapOverview, NoTerrainIsTransparent) {
  const std::vector<glm::dvec3> pos{{0, 0, 0}, {10, 0, 0}, {0, 10, 0}};  // the south-west half only
  const HeightGrid g = rasterizeHeights(pos, {{0, 1, 2}}, {{0, 0}, {10, 10}}, 4, 4);
  const Image8 s = hillshade(g);
  EXPECT_EQ(s.at(0, 3, 1), 255);  // south-west cell
  EXPECT_EQ(s.at(3, 0, 1), 0);    // north-east cell
}

// A prism (LOD1 building) over [x0, x1] x [y0, y1], height h, a vertex per triangle corner.
void addPrism(Mesh& m, double x0, double y0, double x1, double y1, double h, std::uint32_t tag) {
  const auto tri = [&](glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
    const auto n = std::uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), {a, b, c});
    m.triangles.push_back({n, n + 1, n + 2});
    m.triangleTags.push_back(tag);
  };
  const glm::dvec3 a(x0, y0, 0), b(x1, y0, 0), c(x1, y1, 0), d(x0, y1, 0), up(0, 0, h);
  tri(a + up, b + up, c + up);  // roof, counter-clockwise from above
  tri(a + up, c + up, d + up);
  tri(a, b, b + up);  // a south wall
  tri(a, b + up, a + up);
  tri(a, c, b);  // floor, facing down
}

Scene testScene() {
  Scene s;
  s.crs = "EPSG:2154";
  // Terrain: h = 0.1 e over [0, 100]^2.
  s.terrain.positions = {{0, 0, 0}, {100, 0, 10}, {100, 100, 10}, {0, 100, 0}};
  s.terrain.triangles = {{0, 1, 2}, {0, 2, 3}};
  addPrism(s.buildings, 40, 40, 60, 50, 10, 0);
  Photo east, south, far;
  east.camera = lookAtCamera("east", {10, 10, 2}, {20, 10, 2}, 64, 48, 50);
  east.date = "1905";
  south.camera = lookAtCamera("south", {90, 90, 12}, {90, 80, 12}, 64, 48, 50);
  far.camera = lookAtCamera("far", {5e6, 5e6, 2}, {5e6 + 1, 5e6, 2}, 64, 48, 50);
  s.photos = {east, south, far};
  return s;
}

TEST(MapOverview, ExtentFootprintsAndDots) {
  const Scene scene = testScene();
  const MapOverview m = mapOverview(scene, {true, false, false}, 64);
  // The geometry's extent (the far camera left out) with a 5 % margin: [-5, 105]^2.
  EXPECT_NEAR(m.extent.lo.x, -5.0, 1e-9);
  EXPECT_NEAR(m.extent.hi.y, 105.0, 1e-9);
  EXPECT_NEAR(m.groundLevel, 0.0, 1e-9);
  // The footprint: the roof's four outer edges (the diagonal is shared), two triangles filled.
  ASSERT_EQ(m.outlineSegments.size(), 8u);
  EXPECT_EQ(m.footprintTriangles.size(), 6u);
  double perimeter = 0.0;
  for (std::size_t i = 0; i < 8; i += 2) {
    perimeter += glm::distance(m.outlineSegments[i], m.outlineSegments[i + 1]);
    for (const glm::dvec2& p : {m.outlineSegments[i], m.outlineSegments[i + 1]}) {
      EXPECT_TRUE(p.x == 40.0 || p.x == 60.0);
      EXPECT_TRUE(p.y == 40.0 || p.y == 50.0);
    }
  }
  EXPECT_NEAR(perimeter, 60.0, 1e-9);
  // Dots: centres and viewing directions in the plane, dated or not.
  ASSERT_EQ(m.dots.size(), 3u);
  EXPECT_EQ(m.dots[0].at, glm::dvec2(10, 10));
  EXPECT_NEAR(m.dots[0].direction.x, 1.0, 1e-12);
  EXPECT_NEAR(m.dots[1].direction.y, -1.0, 1e-12);
  EXPECT_TRUE(m.dots[0].dated);
  EXPECT_FALSE(m.dots[1].dated);
  // The hillshade: terrain everywhere inside [0, 100]^2, nothing in the margin's corner.
  ASSERT_FALSE(m.shade.data.empty());
  EXPECT_EQ(m.shade.at(m.shade.width / 2, m.shade.height / 2, 1), 255);
  EXPECT_EQ(m.shade.at(0, 0, 1), 0);
  // Terrain heights: h = 0.1 e.
  EXPECT_NEAR(m.groundAt({30, 20}).z, 3.0, 1e-6);
  // On the map, north is up and east right; the east-looking dot points right.
  EXPECT_EQ(pixelDirection(m.dots[1].direction), glm::dvec2(0, 1));  // south: down
}

TEST(MapOverview, ClickPicksADotElseTheGround) {
  const Scene scene = testScene();
  const MapOverview m = mapOverview(scene, {}, 64);
  const MapFrame f = fitMap(m.extent, 220, 220);  // 2 pixels a unit
  // Photograph 1 at (90, 90): pixel (2 * 95, 2 * (105 - 90)) = (190, 30); 4 pixels off still hits.
  MapClick c = clickMap(m, f, {193.0, 27.5}, 6.0);
  EXPECT_EQ(c.photo, 1);
  // 10 pixels off misses: the ground under the click, at the terrain's height.
  c = clickMap(m, f, {200.0, 30.0}, 6.0);
  EXPECT_EQ(c.photo, -1);
  EXPECT_NEAR(c.ground.x, 95.0, 1e-9);
  EXPECT_NEAR(c.ground.y, 90.0, 1e-9);
  EXPECT_NEAR(c.ground.z, 9.5, 1e-6);
  // Going there keeps the view's rotation (heading) and puts it 1.6 above the ground.
  const Camera view = scene.photos[0].camera;
  const Camera there = viewOverGround(view, c.ground, scene.up, 1.6);
  EXPECT_EQ(there.camFromWorld, view.camFromWorld);
  EXPECT_NEAR(there.center.z, 11.1, 1e-6);
  const MapView v = mapView(m, there);
  EXPECT_NEAR(v.at.x, 95.0, 1e-9);
  EXPECT_NEAR(v.direction.x, 1.0, 1e-12);
}

// Zoom and pan (MapZoom) on the box (0, 0)-(100, 50) in a 200 x 200 map: fitted, 2 pixels a unit,
// offset (0, 50); the values below worked by hand from toPixel = offset + ppu (e - 0, 50 - n).
TEST(MapOverview, ZoomOneIsTheFittedMap) {
  const PlaneBox box{{0, 0}, {100, 50}};
  const MapFrame z = zoomedMap(box, 200, 200, MapZoom{}), f = fitMap(box, 200, 200);
  EXPECT_DOUBLE_EQ(z.pixelsPerUnit, f.pixelsPerUnit);
  EXPECT_NEAR(z.offset.x, 0.0, 1e-12);
  EXPECT_NEAR(z.offset.y, 50.0, 1e-12);
}

TEST(MapOverview, ZoomAboutAPixelKeepsItsPlanePointThere) {
  const PlaneBox box{{0, 0}, {100, 50}};
  // Pixel (50, 100) is plane (25, 25). Twice the scale (4 px a unit) with it fixed: centre
  // (25 + 50 / 4, 25) = (37.5, 25); offset (100, 100) - 4 (37.5, 25) = (-50, 0).
  const MapZoom z = zoomAbout(box, 200, 200, MapZoom{}, {50, 100}, 2.0);
  EXPECT_DOUBLE_EQ(z.zoom, 2.0);
  ASSERT_TRUE(z.center);
  EXPECT_NEAR(z.center->x, 37.5, 1e-12);
  EXPECT_NEAR(z.center->y, 25.0, 1e-12);
  const MapFrame f = zoomedMap(box, 200, 200, z);
  EXPECT_DOUBLE_EQ(f.pixelsPerUnit, 4.0);
  EXPECT_NEAR(f.offset.x, -50.0, 1e-12);
  EXPECT_NEAR(f.offset.y, 0.0, 1e-12);
  const glm::dvec2 still = f.toPixel({25, 25});
  EXPECT_NEAR(still.x, 50.0, 1e-12);
  EXPECT_NEAR(still.y, 100.0, 1e-12);
  // Four wheel notches are a factor 2.
  EXPECT_NEAR(wheelZoomFactor(4.0), 2.0, 1e-15);
  EXPECT_NEAR(wheelZoomFactor(-1.0), 1.0 / std::pow(2.0, 0.25), 1e-15);
}

TEST(MapOverview, PanFollowsTheDragWithinTheBox) {
  const PlaneBox box{{0, 0}, {100, 50}};
  const MapZoom z2 = zoomAbout(box, 200, 200, MapZoom{}, {50, 100}, 2.0);  // centre (37.5, 25)
  // 20 pixels right at 4 px a unit: the centre 5 units west, (32.5, 25).
  MapZoom p = panBy(box, 200, 200, z2, {20, 0});
  EXPECT_NEAR(p.center->x, 32.5, 1e-12);
  EXPECT_NEAR(p.center->y, 25.0, 1e-12);
  // 100 pixels right would put the centre at 12.5: the map (50 units wide) would show 12.5 units
  // west of the box; clamped to 25, the box's west edge at the map's left edge.
  p = panBy(box, 200, 200, z2, {100, 0});
  EXPECT_NEAR(p.center->x, 25.0, 1e-12);
  EXPECT_NEAR(zoomedMap(box, 200, 200, p).toPixel({0, 0}).x, 0.0, 1e-12);
  // North-south: 50 units of box in 50 units of map: no room, the centre stays at n = 25.
  p = panBy(box, 200, 200, z2, {0, 30});
  EXPECT_NEAR(p.center->y, 25.0, 1e-12);
  // At zoom 1 a drag does nothing: the fitted map.
  EXPECT_TRUE(panBy(box, 200, 200, MapZoom{}, {40, -30}).whole());
}

TEST(MapOverview, ZoomIsClampedAndZoomingOutReturnsToTheWholeMap) {
  const PlaneBox box{{0, 0}, {100, 50}};
  const MapZoom in = zoomAbout(box, 200, 200, MapZoom{}, {50, 100}, 1000.0);
  EXPECT_DOUBLE_EQ(in.zoom, MapZoomLimits{}.maxZoom);
  EXPECT_DOUBLE_EQ(zoomAbout(box, 200, 200, in, {50, 100}, 1000.0, MapZoomLimits{8.0}).zoom, 8.0);
  const MapZoom out = zoomAbout(box, 200, 200, in, {10, 10}, 1e-6);
  EXPECT_DOUBLE_EQ(out.zoom, 1.0);
  EXPECT_TRUE(out.whole());
  // Nonsense factors change nothing.
  EXPECT_DOUBLE_EQ(zoomAbout(box, 200, 200, in, {10, 10}, std::nan("")).zoom, in.zoom);
  EXPECT_DOUBLE_EQ(zoomAbout(box, 200, 200, in, {10, 10}, -2.0).zoom, in.zoom);
}

TEST(MapOverview, ClickOnAZoomedMap) {
  const Scene scene = testScene();
  const MapOverview m = mapOverview(scene, {}, 64);  // extent (-5, -5)-(105, 105): 2 px a unit in 220
  // Zoom 2 about photograph 1's dot at pixel (190, 30) (plane (90, 90)): centre
  // (90 - 80 / 4, 90 - 80 / 4) = (70, 70), within the limits [22.5, 77.5]; the dot stays.
  const MapZoom z = zoomAbout(m.extent, 220, 220, MapZoom{}, {190, 30}, 2.0);
  EXPECT_NEAR(z.center->x, 70.0, 1e-9);
  const MapFrame f = zoomedMap(m.extent, 220, 220, z);
  EXPECT_EQ(clickMap(m, f, {195.0, 30.0}, 6.0).photo, 1);
  // 10 pixels east is now 2.5 units east (4 px a unit), not 5.
  const MapClick c = clickMap(m, f, {200.0, 30.0}, 6.0);
  EXPECT_EQ(c.photo, -1);
  EXPECT_NEAR(c.ground.x, 92.5, 1e-9);
  EXPECT_NEAR(c.ground.y, 90.0, 1e-9);
}

TEST(MapOverview, AnotherUpUsesThePlaneOrthogonalToIt) {
  // up = -z (an SfM frame): the plane is spanned by upFrame(-z)'s east and north.
  Scene s = testScene();
  s.up = {0, 0, -1};
  const MapOverview m = mapOverview(s, {}, 16);
  EXPECT_NEAR(glm::dot(m.axes.east, s.up), 0.0, 1e-12);
  EXPECT_NEAR(glm::dot(m.axes.north, s.up), 0.0, 1e-12);
  // Roofs face +z, i.e. down there: the floor's one triangle (facing -z) is the footprint.
  EXPECT_EQ(m.footprintTriangles.size(), 3u);
  EXPECT_EQ(m.outlineSegments.size(), 6u);
  // The terrain's heights are measured along -z.
  const glm::dvec3 g = m.groundAt(m.toPlane({30, 20, 0}));
  EXPECT_NEAR(g.z, 3.0, 1e-6);
}

// The orthophoto's rectangle on a z-up map is its scene-frame rectangle less the render origin
// (hand-computed); a map whose plane is not x, y, and an empty orthophoto, get none.
TEST(MapOverview, OrthophotoLiesOnItsSceneRectangle) {
  Orthophoto o;
  o.width = 10;
  o.height = 5;
  o.rgba.assign(10 * 5 * 4, 255);
  o.minX = 651000.0;
  o.maxX = 651100.0;
  o.minY = 6862000.0;
  o.maxY = 6862050.0;
  MapOverview map;  // axes: up z, east x, north y
  const auto box = orthophotoOnMap(map, o, {651020.0, 6862010.0, 35.0});
  ASSERT_TRUE(box.has_value());
  EXPECT_DOUBLE_EQ(box->lo.x, -20.0);
  EXPECT_DOUBLE_EQ(box->lo.y, -10.0);
  EXPECT_DOUBLE_EQ(box->hi.x, 80.0);
  EXPECT_DOUBLE_EQ(box->hi.y, 40.0);

  MapOverview flipped;
  flipped.axes = upFrame({0.0, 0.0, -1.0});  // an SfM frame with up -z: its plane is not x, y
  EXPECT_FALSE(orthophotoOnMap(flipped, o, glm::dvec3(0.0)).has_value());
  EXPECT_FALSE(orthophotoOnMap(map, Orthophoto{}, glm::dvec3(0.0)).has_value());
}

}  // namespace
}  // namespace hv::viewer
