// Terrain rasters, footprints and meshes given in another CRS or unit than the scene's, brought
// into the scene frame (hv/io/georef.h). Expected positions come from closed forms
// (hv/testing/geodesy.h), expected heights from the functions the test rasters were made of.
#include "hv/io/native/footprints.h"
#include "hv/io/native/georef.h"
#include "hv/io/native/raster.h"
#include "hv/io/native/scene_loader.h"
#include "hv/testing/geodesy.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>

namespace hv {
namespace {

namespace fs = std::filesystem;

class SourceCrs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv_source_crs_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(file(name)) << text;
    return file(name);
  }
  void writeSmallSources() const;  // a terrain and a footprint in Paris, a triangle without CRS
  fs::path dir_;
};

bool anyMentions(const std::vector<std::string>& messages, const std::string& text) {
  return std::any_of(messages.begin(), messages.end(),
                     [&](const std::string& m) { return m.find(text) != std::string::npos; });
}

SourceGeoref intoScene(const std::string& sceneCrs, const std::string& crs = "") {
  return {crs, sceneCrs, "scene.json: terrain.crs"};
}

// A raster of `cols` x `rows` cells from the corner (x0, y0), heights z(x, y) at cell centres.
template <class F>
Heightfield grid(int cols, int rows, double x0, double y0, double cell, F z) {
  Heightfield f;
  f.cols = cols;
  f.rows = rows;
  f.originX = x0;
  f.originY = y0;
  f.cellX = cell;
  f.cellY = -cell;
  f.z.resize(size_t(cols) * rows);
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) {
      const glm::dvec2 p = f.samplePosition(i, j);
      f.z[size_t(j) * cols + i] = float(z(p.x, p.y));
    }
  return f;
}

// Paris, 80 x 60 cells of 0.0005 degree (37 m east, 56 m north). Heights a + b u + c v + d u v in
// the offsets u, v from (2.35 E, 48.855 N): slopes of 5 % east and 3 % north, and a twist that
// bilinear interpolation reproduces exactly on the source grid.
constexpr double kLon0 = 2.33, kLat0 = 48.87, kStep = 0.0005;
constexpr double kTwist = 1.0e5;  // m per degree²
double parisHeight(double lon, double lat) {
  const double u = lon - 2.35, v = lat - 48.855;
  return 100.0 + 3660.0 * u + 3336.0 * v + kTwist * u * v;
}

TEST_F(SourceCrs, TerrainInWgs84IsWarpedIntoLambert93) {
  Heightfield src = grid(80, 60, kLon0, kLat0, kStep, parisHeight);
  for (int j = 10; j < 14; ++j)  // a no-data hole of 4 x 4 cells centred on (2.336 E, 48.864 N)
    for (int i = 10; i < 14; ++i) src.z[size_t(j) * src.cols + i] = std::numeric_limits<float>::quiet_NaN();
  writeGeoTiff(file("dtm.tif"), src, "EPSG:4326");

  Diagnostics diag;
  const GeoreferencedHeightfield read = readHeightfield(file("dtm.tif"), intoScene("EPSG:2154"), diag);
  EXPECT_TRUE(diag.ok());
  EXPECT_EQ(read.sourceCrs, "EPSG:4326");
  // Both CRSs are 2D: the heights are kept, and the loader says so.
  EXPECT_TRUE(anyMentions(diag.warnings, "taken as they are")) << ::testing::PrintToString(diag.warnings);
  const Heightfield& f = read.field;
  EXPECT_EQ(f.crs, "EPSG:2154");
  // Square cells of the source's finer side: 0.0005 degree of longitude, 36.6 m at 48.855 N
  // (times Lambert-93's scale factor there, 1 - 2.6e-4... close enough for 0.1 m).
  const double h = std::abs(f.cellX);
  std::printf("  warped %dx%d cells of 0.0005 deg -> %dx%d cells of %.2f m\n", src.cols, src.rows, f.cols, f.rows, h);
  EXPECT_NEAR(std::abs(f.cellY), h, 1e-6 * h);
  EXPECT_NEAR(h, 36.6, 0.1);

  // Points transformed independently (Lambert-93 closed form) find the height of the function at
  // their longitude, latitude. Tolerance: float32 heights (2e-5 m), the closed form against PROJ
  // (< 1 mm, times the 5 % slope), and bilinear interpolation of the twist once the meridian
  // convergence (0.47 degree) turns the axes: below h² d / 8 with d the twist in m⁻², 2 mm at
  // h = 37 m. A misregistration by half a cell (18 m) would cost about 1 m.
  const double twistPerM2 = kTwist / (73200.0 * 111200.0);
  const double tolerance = 1e-3 + h * h * twistPerM2 / 8.0;
  double worst = 0.0;
  int checked = 0;
  for (double lon = kLon0 + 3 * kStep; lon < kLon0 + 77 * kStep; lon += 0.0013)
    for (double lat = kLat0 - 3 * kStep; lat > kLat0 - 57 * kStep; lat -= 0.0011) {
      if (std::abs(lon - 2.336) < 5 * kStep && std::abs(lat - 48.864) < 5 * kStep) continue;  // near the hole
      const glm::dvec2 xy = testing::lambert93(lat, lon);
      const std::optional<double> z = f.elevation(xy.x, xy.y);
      ASSERT_TRUE(z) << lon << " " << lat;
      worst = std::max(worst, std::abs(*z - parisHeight(lon, lat)));
      ++checked;
    }
  std::printf("  %d points: worst height error %.2e m (tolerance %.2e m)\n", checked, worst, tolerance);
  EXPECT_GT(checked, 500);
  EXPECT_LT(worst, tolerance);
  // No-data survives the warp: the middle of the hole has no height.
  const glm::dvec2 hole = testing::lambert93(48.864, 2.336);
  EXPECT_FALSE(f.elevation(hole.x, hole.y));
}

TEST_F(SourceCrs, TerrainHeightsGoThroughProjBetweenVerticalCrss) {
  // Ellipsoidal heights (terrain.crs EPSG:4979, WGS 84 3D) into UTM 31N + EGM96 heights: every
  // sample loses the geoid undulation N (about 45 m at Paris), as PROJ gives it point by point.
  const Heightfield src = grid(40, 30, kLon0, kLat0, 0.001, [](double, double) { return 150.0; });
  writeGeoTiff(file("dtm.tif"), src, "EPSG:4326");
  Diagnostics diag;
  const GeoreferencedHeightfield read =
      readHeightfield(file("dtm.tif"), intoScene("EPSG:32631+5773", "EPSG:4979"), diag);
  EXPECT_TRUE(diag.ok());
  EXPECT_EQ(read.sourceCrs, "EPSG:4979");
  EXPECT_FALSE(anyMentions(diag.warnings, "taken as they are"));
  const GeoTransform direct("EPSG:4979", "EPSG:32631+5773", diag);
  ASSERT_TRUE(direct.transformsHeights());
  for (const auto& [lon, lat] : {std::pair{2.335, 48.865}, std::pair{2.35, 48.855}, std::pair{2.365, 48.845}}) {
    const glm::dvec3 expected = direct.point({lon, lat, 150.0});
    const std::optional<double> z = read.field.elevation(expected.x, expected.y);
    ASSERT_TRUE(z);
    std::printf("  %.3f E %.3f N: 150 m ellipsoidal -> %.3f m EGM96\n", lon, lat, *z);
    EXPECT_GT(150.0 - *z, 40.0);  // the undulation is applied...
    EXPECT_LT(150.0 - *z, 50.0);
    EXPECT_NEAR(*z, expected.z, 2e-3);  // ... and it is PROJ's (N varies by < 1 mm per cell here)
  }
}

TEST_F(SourceCrs, MissingGeoidGridIsReportedNotHidden) {
  // NGF-IGN69 heights need IGN's RAF grid, which is not installed here: PROJ falls back to an
  // operation without it, and the loader must say so rather than mix heights silently.
  const Heightfield src = grid(10, 10, kLon0, kLat0, 0.001, [](double, double) { return 150.0; });
  writeGeoTiff(file("dtm.tif"), src, "EPSG:4326");
  Diagnostics diag;
  readHeightfield(file("dtm.tif"), intoScene("EPSG:2154+5720", "EPSG:4979"), diag);
  EXPECT_TRUE(diag.ok());
  const bool gridMissing = anyMentions(diag.warnings, "not installed");
  const bool ballpark = anyMentions(diag.warnings, "ballpark");
  std::printf("  warnings: %s\n", ::testing::PrintToString(diag.warnings).c_str());
  EXPECT_TRUE(gridMissing || ballpark);
}

TEST_F(SourceCrs, TerrainInFeetComesOutInMetres) {
  {  // EPSG:2994 (Oregon GIC Lambert, international feet), 2D: x, y and heights in feet.
    const Heightfield src =
        grid(20, 10, 636000.0, 849000.0, 10.0,
             [](double x, double y) { return 400.0 + 0.01 * (x - 636000.0) + 0.02 * (849000.0 - y); });
    writeGeoTiff(file("feet.tif"), src, "EPSG:2994");
    Diagnostics diag;
    const GeoreferencedHeightfield read = readHeightfield(file("feet.tif"), intoScene("EPSG:2994"), diag);
    EXPECT_TRUE(diag.ok());
    EXPECT_TRUE(diag.warnings.empty()) << ::testing::PrintToString(diag.warnings);
    const Heightfield& f = read.field;
    ASSERT_EQ(f.cols, src.cols);  // same CRS: no resampling, only units
    ASSERT_EQ(f.rows, src.rows);
    EXPECT_DOUBLE_EQ(f.originX, 636000.0 * 0.3048);
    EXPECT_DOUBLE_EQ(f.originY, 849000.0 * 0.3048);
    EXPECT_DOUBLE_EQ(f.cellX, 10.0 * 0.3048);
    EXPECT_DOUBLE_EQ(f.cellY, -10.0 * 0.3048);
    for (size_t k = 0; k < f.z.size(); ++k) EXPECT_NEAR(f.z[k], src.z[k] * 0.3048, 1e-4) << k;
  }
  {  // A band whose unit type says "ft", in a metre CRS: heights only.
    const Heightfield src =
        grid(5, 4, 651000.0, 6862000.0, 1.0, [](double x, double) { return 100.0 + (x - 651000.0); });
    writeGeoTiff(file("ft-band.tif"), src, "EPSG:2154", "ft");
    Diagnostics diag;
    const GeoreferencedHeightfield read = readHeightfield(file("ft-band.tif"), intoScene("EPSG:2154"), diag);
    EXPECT_TRUE(diag.warnings.empty()) << ::testing::PrintToString(diag.warnings);
    EXPECT_DOUBLE_EQ(read.field.originX, 651000.0);
    for (size_t k = 0; k < src.z.size(); ++k) EXPECT_NEAR(read.field.z[k], src.z[k] * 0.3048, 1e-4) << k;
  }
  {  // A unit GDAL's unit type gives that is not a length: said, and the CRS's unit is used.
    writeGeoTiff(file("furlong.tif"), grid(3, 3, 651000.0, 6862000.0, 1.0, [](double, double) { return 7.0; }),
                 "EPSG:2154", "furlong");
    Diagnostics diag;
    const GeoreferencedHeightfield read = readHeightfield(file("furlong.tif"), intoScene("EPSG:2154"), diag);
    EXPECT_TRUE(anyMentions(diag.warnings, "'furlong' not recognised")) << ::testing::PrintToString(diag.warnings);
    EXPECT_EQ(read.field.z[0], 7.0f);
  }
  {  // Feet into another CRS in metres (UTM 10N): warped, and 1000 ft are 304.8 m everywhere.
    const Heightfield src = grid(30, 30, 636000.0, 849000.0, 20.0, [](double, double) { return 1000.0; });
    writeGeoTiff(file("feet-utm.tif"), src, "EPSG:2994");
    Diagnostics diag;
    const GeoreferencedHeightfield read = readHeightfield(file("feet-utm.tif"), intoScene("EPSG:32610"), diag);
    EXPECT_TRUE(diag.ok());
    EXPECT_NEAR(std::abs(read.field.cellX), 20.0 * 0.3048, 2.0);  // about the source's 6.1 m
    int valid = 0;
    for (float z : read.field.z)
      if (!std::isnan(z)) {
        EXPECT_NEAR(z, 304.8, 1e-3);
        ++valid;
      }
    EXPECT_GT(valid, 600);
  }
}

std::string square(const std::string& crsMember, const std::vector<glm::dvec2>& ring, const std::string& properties) {
  std::string coords;
  for (const glm::dvec2& p : ring) {
    char text[80];
    std::snprintf(text, sizeof(text), "%s[%.10f, %.10f]", coords.empty() ? "" : ", ", p.x, p.y);
    coords += text;
  }
  return R"({"type": "FeatureCollection", )" + crsMember +
         R"("features": [{"type": "Feature", "id": 1, "properties": )" + properties +
         R"(, "geometry": {"type": "Polygon", "coordinates": [[)" + coords + "]]}}]}";
}

// The GeoJSON 2008 `crs` member (GDAL still reads it; RFC 7946 dropped it).
std::string crsMember(const std::string& name) {
  return R"("crs": {"type": "name", "properties": {"name": ")" + name + R"("}}, )";
}

double shoelace(const std::vector<glm::dvec2>& ring) {
  double a = 0.0;
  for (size_t k = 0, prev = ring.size() - 1; k < ring.size(); prev = k++)
    a += ring[prev].x * ring[k].y - ring[k].x * ring[prev].y;
  return 0.5 * std::abs(a);
}

TEST_F(SourceCrs, FootprintsInWgs84GoIntoLambert93) {
  // Lon, lat (RFC 7946 order), closed ring; about 29 m x 33 m.
  const std::vector<glm::dvec2> lonLat = {{2.3500, 48.8500}, {2.3504, 48.8500}, {2.3504, 48.8503}, {2.3500, 48.8503},
                                          {2.3500, 48.8500}};
  std::vector<glm::dvec2> expected;
  for (size_t k = 0; k + 1 < lonLat.size(); ++k) expected.push_back(testing::lambert93(lonLat[k].y, lonLat[k].x));
  // GeoJSON without `crs` is WGS 84 (RFC 7946); the 2008 `crs` member spellings mean the same.
  for (const std::string crs : {std::string(), crsMember("urn:ogc:def:crs:OGC:1.3:CRS84"),
                                crsMember("urn:ogc:def:crs:EPSG::4326")}) {
    SCOPED_TRACE(crs);
    write("b.geojson", square(crs, lonLat, R"({"height": 12.5})"));
    Diagnostics diag;
    const GeoreferencedFootprints read =
        readFootprints(file("b.geojson"), FootprintFields{}, {"", "EPSG:2154", "scene.json: buildings.crs"}, diag);
    EXPECT_TRUE(diag.ok());
    EXPECT_TRUE(diag.warnings.empty()) << ::testing::PrintToString(diag.warnings);
    EXPECT_TRUE(equivalentCrs(read.sourceCrs, "EPSG:4326") || equivalentCrs(read.sourceCrs, "OGC:CRS84"))
        << read.sourceCrs;
    ASSERT_EQ(read.footprints.size(), 1u);
    const auto& ring = read.footprints[0].rings.at(0);
    ASSERT_EQ(ring.size(), expected.size());
    for (size_t k = 0; k < ring.size(); ++k) EXPECT_LT(glm::length(ring[k] - expected[k]), 1e-3) << k;
    EXPECT_EQ(read.footprints[0].height, 12.5);  // a 2D geographic CRS: heights in metres
  }
  // Through the scene: the LOD1 prism's volume is the projected area times the height (1e-6
  // relative: the volume of a mesh 6.9e6 m from the origin cancels far larger terms).
  write("scene.json", R"({"crs": "EPSG:2154", "buildings": {"path": "b.geojson", "height": "height"}})");
  Diagnostics diag;
  const Scene scene = loadScene(file("scene.json"), diag);
  EXPECT_TRUE(diag.ok());
  const double area = shoelace(expected);
  EXPECT_NEAR(scene.buildings.signedVolume(), area * 12.5, 1e-6 * area * 12.5);
  ASSERT_EQ(scene.sourceCrs.size(), 1u);
  EXPECT_EQ(scene.sourceCrs[0].source, "buildings");
  EXPECT_TRUE(scene.sourceCrs[0].transformed);
}

TEST_F(SourceCrs, ProjectedGeoJsonWithoutCrsIsTakenInTheSceneCrs) {
  // Pre-RFC 7946 files often hold projected coordinates and no `crs`: GDAL calls them WGS 84, but
  // 651000 is no longitude. Taken in the scene CRS, with a warning, rather than lost.
  const std::vector<glm::dvec2> ring = {{651000, 6862000}, {651010, 6862000}, {651010, 6862010}, {651000, 6862000}};
  write("b.geojson", square("", ring, R"({"height": 10})"));
  Diagnostics diag;
  const GeoreferencedFootprints read =
      readFootprints(file("b.geojson"), FootprintFields{}, {"", "EPSG:2154", "scene.json: buildings.crs"}, diag);
  EXPECT_TRUE(anyMentions(diag.warnings, "not longitudes and latitudes")) << ::testing::PrintToString(diag.warnings);
  EXPECT_EQ(read.sourceCrs, "EPSG:2154");
  ASSERT_EQ(read.footprints.size(), 1u);
  EXPECT_EQ(read.footprints[0].rings[0][1], glm::dvec2(651010, 6862000));
}

TEST_F(SourceCrs, FootprintsInFeetComeOutInMetres) {
  // 100 ft x 100 ft, 30 ft high, base 10 ft: a 2D CRS in feet has its heights in feet.
  const std::vector<glm::dvec2> ring = {
      {636000, 849000}, {636100, 849000}, {636100, 849100}, {636000, 849100}, {636000, 849000}};
  write("b.geojson", square(crsMember("urn:ogc:def:crs:EPSG::2994"), ring, R"({"height": 30, "base": 10})"));
  FootprintFields fields;
  fields.base = "base";
  Diagnostics diag;
  const GeoreferencedFootprints read =
      readFootprints(file("b.geojson"), fields, {"", "EPSG:2994", "scene.json: buildings.crs"}, diag);
  EXPECT_TRUE(diag.warnings.empty()) << ::testing::PrintToString(diag.warnings);
  ASSERT_EQ(read.footprints.size(), 1u);
  const Footprint& fp = read.footprints[0];
  for (size_t k = 0; k < 4; ++k) EXPECT_LT(glm::length(fp.rings[0][k] - ring[k] * 0.3048), 1e-6) << k;
  EXPECT_NEAR(*fp.height, 30.0 * 0.3048, 1e-9);
  EXPECT_NEAR(*fp.base, 10.0 * 0.3048, 1e-9);

  write("scene.json", R"({"crs": "EPSG:2994", "buildings": {"path": "b.geojson", "base": "base"}})");
  const Scene scene = loadScene(file("scene.json"), diag);
  EXPECT_TRUE(diag.ok());
  const double side = 100.0 * 0.3048, height = 30.0 * 0.3048;
  // 1e-6 relative: the divergence-theorem volume of a mesh 2.6e5 m from the origin cancels terms
  // 1e8 times larger than the result.
  EXPECT_NEAR(scene.buildings.signedVolume(), side * side * height, 1e-6 * side * side * height);
  EXPECT_NEAR(scene.buildings.bounds().lo.z, 10.0 * 0.3048, 1e-9);

  // Into another CRS, the absolute base cannot change datum (both CRSs are 2D): kept, and said.
  Diagnostics other;
  readFootprints(file("b.geojson"), fields, {"", "EPSG:32610", "scene.json: buildings.crs"}, other);
  EXPECT_TRUE(anyMentions(other.warnings, "taken as they are")) << ::testing::PrintToString(other.warnings);
}

TEST_F(SourceCrs, FootprintLevelsGoThroughProjBetweenVerticalCrss) {
  // Absolute base and roof given as ellipsoidal heights (buildings.crs EPSG:4979) into UTM 31N +
  // EGM96: both lose the geoid undulation at the footprint; the relative height does not.
  const std::vector<glm::dvec2> ring = {{2.35, 48.85}, {2.3504, 48.85}, {2.3504, 48.8503}, {2.35, 48.85}};
  write("b.geojson", square("", ring, R"({"height": 20, "base": 150, "top": 170})"));
  FootprintFields fields;
  fields.base = "base";
  fields.top = "top";
  Diagnostics diag;
  const GeoreferencedFootprints read =
      readFootprints(file("b.geojson"), fields, {"EPSG:4979", "EPSG:32631+5773", "scene.json: buildings.crs"}, diag);
  EXPECT_TRUE(diag.warnings.empty()) << ::testing::PrintToString(diag.warnings);
  ASSERT_EQ(read.footprints.size(), 1u);
  const GeoTransform direct("EPSG:4979", "EPSG:32631+5773", diag);
  const Footprint& fp = read.footprints[0];
  EXPECT_NEAR(*fp.base, direct.point({2.35, 48.85, 150.0}).z, 1e-6);
  EXPECT_NEAR(*fp.top, direct.point({2.35, 48.85, 170.0}).z, 1e-6);
  EXPECT_GT(150.0 - *fp.base, 40.0);  // the undulation, about 45 m here
  EXPECT_EQ(fp.height, 20.0);
}

TEST_F(SourceCrs, MeshCrsMovesTheMesh) {
  write("m.obj", "v 2.35 48.85 35\nv 2.3504 48.85 36\nv 2.35 48.8503 37\nf 1 2 3\n");
  write("scene.json", R"({"crs": "EPSG:2154", "mesh": {"path": "m.obj", "crs": "EPSG:4326"}})");
  Diagnostics diag;
  const Scene scene = loadScene(file("scene.json"), diag);
  EXPECT_TRUE(diag.ok());
  ASSERT_EQ(scene.mesh.positions.size(), 3u);
  // Assimp reads single-precision coordinates (0.4 m at this longitude): compare with the floats.
  const glm::dvec2 lonLat[3] = {glm::vec2(2.35, 48.85), glm::vec2(2.3504, 48.85), glm::vec2(2.35, 48.8503)};
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3& p = scene.mesh.positions[size_t(k)];
    EXPECT_LT(glm::length(glm::dvec2(p) - testing::lambert93(lonLat[k].y, lonLat[k].x)), 1e-3) << k;
    EXPECT_NEAR(p.z, 35.0 + k, 1e-9);  // 2D to 2D: heights pass through
  }
  ASSERT_EQ(scene.sourceCrs.size(), 1u);
  EXPECT_EQ(scene.sourceCrs[0].source, "mesh");
  // Without mesh.crs the mesh is in the scene frame as it is.
  write("scene.json", R"({"crs": "EPSG:2154", "mesh": {"path": "m.obj"}})");
  EXPECT_EQ(loadScene(file("scene.json"), diag).mesh.positions[0], glm::dvec3(glm::vec3(2.35f, 48.85f, 35.0f)));
}

// The terrain in Lambert-93, the footprint in WGS 84 (GeoJSON without `crs`).
void SourceCrs::writeSmallSources() const {
  writeGeoTiff(file("dtm.tif"), grid(10, 10, 651000.0, 6862010.0, 1.0, [](double, double) { return 35.0; }),
               "EPSG:2154");
  const std::vector<glm::dvec2> triangle = {{2.35, 48.85}, {2.3504, 48.85}, {2.3504, 48.8503}, {2.35, 48.85}};
  write("b.geojson", square("", triangle, R"({"height": 10})"));
  write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
}

// scene.json's sources with a `crs` each (JSON text; empty: none).
std::string sources(const std::string& terrainCrs, const std::string& buildingsCrs, const std::string& meshCrs) {
  auto crs = [](const std::string& c) { return c.empty() ? std::string() : ", \"crs\": " + c; };
  return R"("terrain": {"path": "dtm.tif")" + crs(terrainCrs) + R"(}, "buildings": {"path": "b.geojson")" +
         crs(buildingsCrs) + R"(}, "mesh": {"path": "m.obj")" + crs(meshCrs) + "}";
}

TEST_F(SourceCrs, BadCrsNamesTheFieldAndTheRestLoads) {
  writeSmallSources();
  for (const auto& [source, json] : std::vector<std::pair<std::string, std::string>>{
           {"terrain", sources(R"("EPSG:99999999")", "", "")},
           {"terrain", sources("2154", "", "")},
           {"buildings", sources("", R"("bogus")", "")},
           {"mesh", sources("", "", R"("+proj=nonsense")")}}) {
    SCOPED_TRACE(json);
    write("scene.json", R"({"crs": "EPSG:2154", )" + json + "}");
    Diagnostics diag;
    const Scene scene = loadScene(file("scene.json"), diag);
    ASSERT_EQ(diag.errors.size(), 1u) << ::testing::PrintToString(diag.errors);
    EXPECT_NE(diag.errors[0].find(source + ".crs"), std::string::npos) << diag.errors[0];
    EXPECT_NE(diag.errors[0].find(source + " left out"), std::string::npos) << diag.errors[0];
    EXPECT_EQ(scene.terrain.empty(), source == "terrain");
    EXPECT_EQ(scene.buildings.empty(), source == "buildings");
    EXPECT_EQ(scene.mesh.empty(), source == "mesh");
  }
  // A heightfield cannot go into a geocentric scene (z is not up there): an error, not a crash.
  write("scene.json", R"({"crs": "EPSG:4978", )" + sources("", "", "") + "}");
  Diagnostics diag;
  const Scene scene = loadScene(file("scene.json"), diag);
  EXPECT_TRUE(scene.terrain.empty());
  EXPECT_TRUE(scene.buildings.empty());
  EXPECT_FALSE(scene.mesh.empty());
  EXPECT_TRUE(anyMentions(diag.errors, "geocentric")) << ::testing::PrintToString(diag.errors);
}

TEST_F(SourceCrs, WithoutSceneCrsSourcesAreTakenAsTheyAre) {
  writeSmallSources();
  write("scene.json", "{" + sources("", "", "") + "}");
  Diagnostics diag;
  const Scene scene = loadScene(file("scene.json"), diag);
  EXPECT_TRUE(diag.ok());
  EXPECT_NEAR(scene.terrain.bounds().lo.x, 651000.5, 1e-9);  // not moved
  EXPECT_NEAR(scene.buildings.bounds().lo.x, 2.35, 1e-9);
  ASSERT_EQ(scene.sourceCrs.size(), 2u);  // the mesh declares none
  EXPECT_FALSE(scene.sourceCrs[0].transformed);
  // ... and since they declare different CRSs, the loader says so once.
  EXPECT_EQ(std::count_if(diag.warnings.begin(), diag.warnings.end(),
                          [](const std::string& w) { return w.find("declare the scene's crs") != std::string::npos; }),
            1);
  // Sources that agree need no warning.
  write("scene.json", "{" + sources("", R"("EPSG:2154")", "") + "}");
  Diagnostics agree;
  loadScene(file("scene.json"), agree);
  EXPECT_FALSE(anyMentions(agree.warnings, "declare the scene's crs")) << ::testing::PrintToString(agree.warnings);
}

}  // namespace
}  // namespace hv
