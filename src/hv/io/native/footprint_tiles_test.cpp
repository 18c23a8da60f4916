// Footprints read by tile (readFootprintTiles) against the whole read (readFootprints), on real
// GeoPackage and Shapefile layers written here with OGR.
#include "hv/camera/camera.h"
#include "hv/image/native/png_write.h"
#include "hv/io/cameras_json.h"
#include "hv/io/native/footprints.h"
#include "hv/io/native/scene_loader.h"
#include "hv/scene/native/lod1.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogrsf_frmts.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

namespace hv {
namespace {

namespace fs = std::filesystem;

struct Building {
  std::vector<std::vector<glm::dvec2>> rings;  // not closed
  double height;
};

// A 200 m x 200 m block: a 5 x 5 grid of 20 m squares (one with a courtyard), a 180 m bar that
// crosses every 50 m tile border along x, an L-shaped building whose first vertex is in one tile and
// whose bulk is in others, and a tall tower at a tile corner.
std::vector<Building> blockOfBuildings() {
  std::vector<Building> out;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) {
      const double x = 5.0 + 40.0 * i, y = 5.0 + 40.0 * j;
      Building b{{{{x, y}, {x + 20, y}, {x + 20, y + 20}, {x, y + 20}}}, 6.0 + i + 2.0 * j};
      if (i == 2 && j == 2) b.rings.push_back({{x + 5, y + 5}, {x + 5, y + 15}, {x + 15, y + 15}, {x + 15, y + 5}});
      out.push_back(b);
    }
  out.push_back({{{{10, 28}, {190, 28}, {190, 32}, {10, 32}}}, 9.5});                             // the bar
  out.push_back({{{{48, 148}, {48, 190}, {140, 190}, {140, 186}, {52, 186}, {52, 148}}}, 12.0});  // the L
  out.push_back({{{{98, 98}, {102, 98}, {102, 102}, {98, 102}}}, 80.0});  // the tower on the corner (100, 100)
  return out;
}

double ringArea(const std::vector<glm::dvec2>& r) {
  double a = 0.0;
  for (size_t k = 0; k < r.size(); ++k) a += r[k].x * r[(k + 1) % r.size()].y - r[(k + 1) % r.size()].x * r[k].y;
  return 0.5 * std::abs(a);
}

double footprintArea(const std::vector<std::vector<glm::dvec2>>& rings) {
  double a = ringArea(rings[0]);
  for (size_t h = 1; h < rings.size(); ++h) a -= ringArea(rings[h]);
  return a;
}

class FootprintTiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv_footprint_tiles_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    GDALAllRegister();
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The buildings as a layer of `driver` ("GPKG", "ESRI Shapefile"), in a local projected CRS.
  std::string write(const std::string& driver, const std::string& name, const std::vector<Building>& buildings) {
    const std::string path = (dir_ / name).string();
    GDALDriver* d = GetGDALDriverManager()->GetDriverByName(driver.c_str());
    if (!d) throw std::runtime_error("no " + driver + " driver");
    GDALDataset* ds = d->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr);
    if (!ds) throw std::runtime_error("cannot create " + path);
    OGRSpatialReference srs;
    srs.importFromEPSG(2154);
    OGRLayer* layer = ds->CreateLayer("buildings", &srs, wkbPolygon, nullptr);
    OGRFieldDefn height("height", OFTReal);
    layer->CreateField(&height);
    for (const Building& b : buildings) {
      OGRFeature f(layer->GetLayerDefn());
      f.SetField("height", b.height);
      OGRPolygon polygon;
      for (const auto& ring : b.rings) {
        OGRLinearRing r;
        for (const glm::dvec2& p : ring) r.addPoint(700000.0 + p.x, 6600000.0 + p.y);
        r.addPoint(700000.0 + ring[0].x, 6600000.0 + ring[0].y);
        polygon.addRing(&r);
      }
      f.SetGeometry(&polygon);
      if (layer->CreateFeature(&f) != OGRERR_NONE) throw std::runtime_error("cannot write a feature");
    }
    GDALClose(ds);
    return path;
  }

  fs::path dir_;
};

struct TiledRead {
  FootprintTileSource source;
  std::vector<FootprintTile> tiles;
  Diagnostics diag;
};

TiledRead readTiles(const std::string& path, FootprintTileOptions options) {
  TiledRead r;
  r.source = readFootprintTiles(
      path, FootprintFields{}, SourceGeoref{}, options, [&](FootprintTile& t) { r.tiles.push_back(t); }, r.diag);
  return r;
}

// The LOD1 mesh of the tiles, extruded tile by tile as the scene loader does (base 0).
Mesh extrudeTiles(const std::vector<FootprintTile>& tiles, Diagnostics& diag) {
  Mesh all;
  for (const FootprintTile& t : tiles) all.append(buildLod1(t.footprints, nullptr, diag));
  return all;
}

// The same checks for any source: each building once, in the tile of its first vertex, and the
// union of the tiles equal to the whole read (area and volume, and independent values).
void expectSameAsWhole(const std::string& path, const std::vector<Building>& buildings, const TiledRead& tiled) {
  Diagnostics diag;
  const std::vector<Footprint> whole = readFootprints(path, FootprintFields{}, diag);
  ASSERT_EQ(whole.size(), buildings.size());
  std::map<std::string, int> seen;
  for (const FootprintTile& t : tiled.tiles)
    for (const Footprint& f : t.footprints) {
      ++seen[f.id];
      // Owned by the tile holding its first vertex (the box is closed; 0.5 m of slack for the
      // layer's own coordinates).
      const glm::dvec2 v = f.rings[0][0];
      EXPECT_TRUE(v.x >= t.lo.x && v.x <= t.hi.x && v.y >= t.lo.y && v.y <= t.hi.y) << f.id;
    }
  EXPECT_EQ(seen.size(), whole.size());
  for (const auto& [id, n] : seen) EXPECT_EQ(n, 1) << "footprint " << id << " read " << n << " times";

  Mesh wholeMesh = buildLod1(whole, nullptr, diag);
  Mesh tiledMesh = extrudeTiles(tiled.tiles, diag);
  EXPECT_EQ(tiledMesh.triangles.size(), wholeMesh.triangles.size());
  double expectedVolume = 0.0, expectedFootprints = 0.0;
  for (const Building& b : buildings) {
    expectedFootprints += footprintArea(b.rings);
    expectedVolume += footprintArea(b.rings) * b.height;
  }
  double tiledFootprints = 0.0;
  for (const FootprintTile& t : tiled.tiles)
    for (const Footprint& f : t.footprints) tiledFootprints += footprintArea(f.rings);
  EXPECT_NEAR(tiledFootprints, expectedFootprints, 1e-6 * expectedFootprints);
  EXPECT_NEAR(tiledMesh.signedVolume(), expectedVolume, 1e-6 * expectedVolume);
  EXPECT_NEAR(tiledMesh.signedVolume(), wholeMesh.signedVolume(), 1e-6 * expectedVolume);
  EXPECT_NEAR(tiledMesh.area(), wholeMesh.area(), 1e-6 * wholeMesh.area());
}

TEST_F(FootprintTiles, GeoPackageThroughTheSpatialFilterReadsEachBuildingOnce) {
  const std::vector<Building> buildings = blockOfBuildings();
  const std::string path = write("GPKG", "buildings.gpkg", buildings);
  FootprintTileOptions options;
  options.tileSize = 50.0;
  const TiledRead tiled = readTiles(path, options);
  EXPECT_TRUE(tiled.source.spatialFilter);
  EXPECT_EQ(tiled.source.note, "");
  // The extent, 5..190 (185 m) in 50 m tiles: 4 x 4.
  EXPECT_EQ(tiled.source.tilesTotal, 16u);
  EXPECT_EQ(tiled.source.tilesRead, 16u);
  EXPECT_GT(tiled.tiles.size(), 8u);
  expectSameAsWhole(path, buildings, tiled);
  EXPECT_TRUE(tiled.diag.warnings.empty()) << tiled.diag.warnings.front();
  // The bar crosses three tile borders yet is in one tile: the first one along x.
  for (const FootprintTile& t : tiled.tiles)
    for (const Footprint& f : t.footprints)
      if (std::abs(footprintArea(f.rings) - 180.0 * 4.0) < 1e-6) EXPECT_DOUBLE_EQ(t.lo.x, 700005.0);
}

TEST_F(FootprintTiles, DensityChoosesTheTileSize) {
  const std::vector<Building> buildings = blockOfBuildings();
  const std::string path = write("GPKG", "buildings.gpkg", buildings);
  FootprintTileOptions options;
  options.perTile = 7;  // 28 features over 185 m x 185 m: 4 tiles of 92.5 m
  const TiledRead tiled = readTiles(path, options);
  EXPECT_NEAR(tiled.source.tileSize, 92.5, 1e-9);
  EXPECT_EQ(tiled.source.tilesTotal, 4u);
  expectSameAsWhole(path, buildings, tiled);
}

TEST_F(FootprintTiles, ShapefileWithoutIndexIsIndexedInMemoryWithTheSameResult) {
  const std::vector<Building> buildings = blockOfBuildings();
  const std::string path = write("ESRI Shapefile", "buildings.shp", buildings);
  ASSERT_FALSE(fs::exists(dir_ / "buildings.qix"));
  FootprintTileOptions options;
  options.tileSize = 50.0;
  const TiledRead tiled = readTiles(path, options);
  EXPECT_FALSE(tiled.source.spatialFilter);
  EXPECT_NE(tiled.source.note.find("indexed in memory"), std::string::npos) << tiled.source.note;
  EXPECT_EQ(tiled.source.tilesTotal, 16u);
  expectSameAsWhole(path, buildings, tiled);

  // The same tiles as the GeoPackage's, footprint by footprint.
  const std::string gpkg = write("GPKG", "buildings.gpkg", buildings);
  const TiledRead indexed = readTiles(gpkg, options);
  ASSERT_EQ(indexed.tiles.size(), tiled.tiles.size());
  for (size_t k = 0; k < tiled.tiles.size(); ++k) {
    EXPECT_EQ(indexed.tiles[k].lo, tiled.tiles[k].lo);
    EXPECT_EQ(indexed.tiles[k].footprints.size(), tiled.tiles[k].footprints.size());
  }
}

TEST_F(FootprintTiles, OnlyTheWantedTilesAreRead) {
  const std::vector<Building> buildings = blockOfBuildings();
  for (const std::string& driver : {std::string("GPKG"), std::string("ESRI Shapefile")}) {
    const std::string path = write(driver, driver == "GPKG" ? "b.gpkg" : "b.shp", buildings);
    FootprintTileOptions options;
    options.tileSize = 50.0;
    options.wanted = [](glm::dvec2 lo, glm::dvec2) { return lo.x < 700000.0 + 50.0; };  // the first column
    const TiledRead tiled = readTiles(path, options);
    EXPECT_EQ(tiled.source.tilesRead, 4u) << driver;
    // Owned by the first column (x in 5..55): the squares of x = 5 and 45 (10), the bar (first
    // vertex x = 10) and the L (x = 48); the tower's first vertex is at x = 98.
    size_t n = 0;
    for (const FootprintTile& t : tiled.tiles) n += t.footprints.size();
    EXPECT_EQ(n, 10u + 1u + 1u) << driver;
  }
}

// The scene loader reads only the tiles the photographs may see: a 3 km x 3 km town of 30 x 30
// buildings, one photograph in a corner looking along x with a focal of 50 px (reach 200 m).
TEST_F(FootprintTiles, SceneLoadsTheTilesThePhotographsSee) {
  std::vector<Building> town;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) {
      const double x = 100.0 * i, y = 100.0 * j;
      town.push_back({{{{x, y}, {x + 20, y}, {x + 20, y + 20}, {x, y + 20}}}, 10.0});
    }
  write("GPKG", "town.gpkg", town);
  Photo photo;
  photo.camera = lookAtCamera("corner", {700000.0 + 50.0, 6600000.0 + 50.0, 2.0},
                              {700000.0 + 1000.0, 6600000.0 + 50.0, 2.0}, 100, 100, 50.0);
  photo.imagePath = (dir_ / "corner.png").string();
  writePng(photo.imagePath, Image8(100, 100, 3, std::uint8_t(128)));
  std::ofstream(dir_ / "cameras.json") << cameraJson({photo}, dir_.string());
  std::ofstream(dir_ / "with.json") << R"({"crs": "EPSG:2154", "buildings": {"path": "town.gpkg"},
                                           "cameras": {"path": "cameras.json"}})";
  std::ofstream(dir_ / "without.json") << R"({"crs": "EPSG:2154", "buildings": {"path": "town.gpkg"}})";

  Diagnostics diag;
  const Scene all = loadScene((dir_ / "without.json").string(), diag);
  EXPECT_EQ(all.buildingTilesInfo.loaded, all.buildingTilesInfo.total);
  EXPECT_EQ(all.buildingValidity.size(), 900u);
  EXPECT_EQ(all.tileOfBuilding.size(), 900u);
  // 900 buildings, 256 a tile: 2 x 2 tiles.
  EXPECT_EQ(all.buildingTilesInfo.total, 4u);
  EXPECT_TRUE(all.buildingTilesInfo.spatialFilter);

  const Scene seen = loadScene((dir_ / "with.json").string(), diag);
  ASSERT_EQ(seen.photos.size(), 1u);
  EXPECT_EQ(seen.buildingTilesInfo.total, 4u);
  // The photograph sees 200 m along the first row: only the first tile.
  EXPECT_EQ(seen.buildingTilesInfo.loaded, 1u);
  EXPECT_EQ(seen.buildingValidity.size(), 16u * 16u);  // x, y < 1557 (tiles of 1557 m)
  EXPECT_EQ(seen.tileOfBuilding.size(), seen.buildingValidity.size());
  // Every building the photograph sees within reach is there: those of the first row up to x = 250.
  const Aabb box = seen.buildings.bounds();
  EXPECT_LE(box.lo.x, 700000.0 + 1.0);
  EXPECT_GE(box.hi.x, 700000.0 + 300.0);
}

}  // namespace
}  // namespace hv

namespace hv {
namespace {

// The tiles read on demand (footprintTileSet, what the renderer streams) are, together, the
// whole load: each building once (the bar across three borders included), the same triangles,
// area and volume, read from several threads at once.
TEST_F(FootprintTiles, TileSetReadOnDemandIsTheWholeLoadEachBuildingOnce) {
  const std::vector<Building> buildings = blockOfBuildings();
  double expectedVolume = 0.0;
  for (const Building& b : buildings) expectedVolume += footprintArea(b.rings) * b.height;
  for (const std::string& driver : {std::string("GPKG"), std::string("ESRI Shapefile")}) {
    const std::string path = write(driver, driver == "GPKG" ? "b.gpkg" : "b.shp", buildings);
    FootprintTileOptions options;
    options.tileSize = 50.0;
    FootprintTileSource info;
    Diagnostics diag;
    const auto set =
        footprintTileSet(path, FootprintFields{}, SourceGeoref{}, options, nullptr, -5.0, 200.0, info, diag);
    ASSERT_TRUE(set && set->read) << driver;
    EXPECT_EQ(info.tilesTotal, 16u) << driver;
    EXPECT_EQ(info.features, buildings.size()) << driver;
    EXPECT_EQ(set->boxes.size(), 16u) << driver;
    EXPECT_EQ(info.spatialFilter, driver == "GPKG") << driver;
    EXPECT_EQ(info.note.empty(), driver == "GPKG") << info.note;
    EXPECT_TRUE(diag.ok()) << driver;
    // Tile 0 is the cell 5..55 x 5..55, widened by a cell each side, at the heights given.
    EXPECT_DOUBLE_EQ(set->boxes[0].lo.x, 700005.0 - 50.0);
    EXPECT_DOUBLE_EQ(set->boxes[0].hi.x, 700055.0 + 50.0);
    EXPECT_DOUBLE_EQ(set->boxes[0].lo.z, -5.0);
    EXPECT_DOUBLE_EQ(set->boxes[0].hi.z, 200.0);

    // Every tile, half of them on another thread at the same time.
    std::vector<BuildingTileData> tiles(set->boxes.size());
    std::thread other([&] {
      for (std::uint32_t t = 0; t < tiles.size(); t += 2) tiles[t] = set->read(t);
    });
    for (std::uint32_t t = 1; t < tiles.size(); t += 2) tiles[t] = set->read(t);
    other.join();
    Mesh all;
    std::size_t footprints = 0;
    for (const BuildingTileData& d : tiles) {
      // Each tile's warnings come with it: here, one a footprint (no terrain, base at 0).
      EXPECT_EQ(d.warnings.size(), d.validity.size());
      for (const std::string& w : d.warnings) EXPECT_NE(w.find("base set to 0"), std::string::npos) << w;
      EXPECT_EQ(d.mesh.triangleTags.size(), d.mesh.triangles.size());
      for (std::uint32_t tag : d.mesh.triangleTags) EXPECT_LT(tag, d.validity.size());
      footprints += d.validity.size();
      all.append(d.mesh);
    }
    EXPECT_EQ(footprints, buildings.size()) << driver << ": a building read twice or never";
    const Mesh whole = buildLod1(readFootprints(path, FootprintFields{}, diag), nullptr, diag);
    EXPECT_EQ(all.triangles.size(), whole.triangles.size()) << driver;
    EXPECT_NEAR(all.area(), whole.area(), 1e-6 * whole.area()) << driver;
    EXPECT_NEAR(all.signedVolume(), expectedVolume, 1e-6 * expectedVolume) << driver;
    // The bar (180 m x 4 m, 9.5 m tall) in exactly one tile: the first along x.
    int barTiles = 0;
    for (std::size_t t = 0; t < tiles.size(); ++t)
      if (tiles[t].mesh.bounds().size().x > 170.0) {
        ++barTiles;
        EXPECT_EQ(t % 4, 0u);
      }
    EXPECT_EQ(barTiles, 1) << driver;
    EXPECT_THROW(set->read(99), std::exception) << driver;
  }
}

// A reader kept open (what each streaming thread holds): tile after tile, in any order and again,
// the same footprints as readFootprintTiles reading only that tile, with the layer's CRS
// transform made once; a source that cannot be opened is named.
TEST_F(FootprintTiles, ReaderKeptOpenReadsEachTileAsAReadOfThatTileAlone) {
  const std::vector<Building> buildings = blockOfBuildings();
  const std::string path = write("GPKG", "kept.gpkg", buildings);
  FootprintTileOptions options;
  options.tileSize = 50.0;
  SourceGeoref georef;
  georef.sceneCrs = "EPSG:32631";  // UTM 31N: the footprints are transformed from EPSG:2154
  FootprintTileReader reader(path, FootprintFields{}, georef, options);
  ASSERT_EQ(reader.tiles(), 16u);
  std::size_t footprints = 0;
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t k = 0; k < 16; ++k) {
      const std::size_t tile = pass == 0 ? k : 15 - k;  // backwards the second time
      FootprintTileOptions one = options;
      std::size_t asked = 0;
      one.wanted = [&asked, tile](glm::dvec2, glm::dvec2) { return asked++ == tile; };
      std::vector<Footprint> expected;
      Diagnostics expectedDiag, diag;
      readFootprintTiles(
          path, FootprintFields{}, georef, one,
          [&](FootprintTile& t) {
            for (Footprint& f : t.footprints) expected.push_back(std::move(f));
          },
          expectedDiag);
      const std::vector<Footprint> got = reader.read(tile, diag);
      ASSERT_EQ(got.size(), expected.size()) << "tile " << tile;
      for (std::size_t i = 0; i < got.size(); ++i) {
        EXPECT_EQ(got[i].id, expected[i].id);
        EXPECT_EQ(got[i].rings, expected[i].rings) << got[i].id;  // bit for bit
        EXPECT_EQ(got[i].height, expected[i].height);
      }
      EXPECT_EQ(diag.warnings, expectedDiag.warnings);
      EXPECT_EQ(diag.errors, expectedDiag.errors);
      if (pass == 0) footprints += got.size();
    }
  EXPECT_EQ(footprints, buildings.size());
  // Transformed: UTM 31N eastings of Lambert-93's 700 km are about 450 km, not 700 km.
  Diagnostics diag;
  const std::vector<Footprint> first = reader.read(0, diag);
  ASSERT_FALSE(first.empty());
  EXPECT_LT(first[0].rings[0][0].x, 690000.0);
  EXPECT_THROW(reader.read(16, diag), std::out_of_range);
  try {
    FootprintTileReader missing((dir_ / "missing.gpkg").string(), FootprintFields{}, georef, options);
    ADD_FAILURE() << "a missing source opened";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("missing.gpkg"), std::string::npos) << e.what();
  }
}

// The load's tiles extruded on several threads at once: the same meshes (bit for bit), dates and
// warnings, in the same order, as extruding them one after the other.
TEST_F(FootprintTiles, ExtrudedOnSeveralThreadsAsOneAfterTheOther) {
  const std::vector<Building> buildings = blockOfBuildings();
  const std::string path = write("GPKG", "threads.gpkg", buildings);
  FootprintTileOptions options;
  options.tileSize = 50.0;
  const TiledRead tiled = readTiles(path, options);
  ASSERT_GT(tiled.tiles.size(), 4u);
  std::vector<std::vector<Footprint>> footprints;
  for (const FootprintTile& t : tiled.tiles) footprints.push_back(t.footprints);
  Diagnostics sequentialDiag;
  std::vector<BuildingTileData> sequential;
  for (const auto& f : footprints)
    sequential.push_back(extrudeFootprintTile(f, nullptr, FootprintFields{}, path, sequentialDiag));
  ASSERT_FALSE(sequentialDiag.warnings.empty());  // "base set to 0": one a footprint, in order
  for (int threads : {1, 3, 0}) {
    Diagnostics diag;
    const std::vector<BuildingTileData> parallel =
        extrudeFootprintTiles(footprints, nullptr, FootprintFields{}, path, diag, threads);
    ASSERT_EQ(parallel.size(), sequential.size()) << threads;
    for (std::size_t t = 0; t < parallel.size(); ++t) {
      EXPECT_EQ(parallel[t].mesh.positions, sequential[t].mesh.positions) << "tile " << t << ", " << threads;
      EXPECT_EQ(parallel[t].mesh.triangles, sequential[t].mesh.triangles) << "tile " << t << ", " << threads;
      EXPECT_EQ(parallel[t].mesh.triangleTags, sequential[t].mesh.triangleTags) << "tile " << t;
      EXPECT_EQ(parallel[t].validity, sequential[t].validity) << "tile " << t;
    }
    EXPECT_EQ(diag.warnings, sequentialDiag.warnings) << threads;
    EXPECT_EQ(diag.errors, sequentialDiag.errors) << threads;
  }
  Diagnostics none;
  EXPECT_TRUE(extrudeFootprintTiles({}, nullptr, FootprintFields{}, path, none).empty());
}

}  // namespace
}  // namespace hv
