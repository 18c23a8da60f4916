// CityJSON buildings (hv/io/native/cityjson.h): a hand-written file with exact values, and the
// real Delft file against the same buildings' footprints and heights.
#include "hv/io/native/cityjson.h"

#include "hv/io/native/footprints.h"
#include "hv/io/native/scene_loader.h"
#include "hv/scene/native/lod1.h"
#include "hv/testing/data_dir.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

namespace hv {
namespace {

// Per building (triangle tag): what the comparisons need.
struct Stats {
  double floorArea = 0.0;  // down-facing horizontal triangles, projected
  glm::dvec2 floorCentre{0.0};
  double roofArea = 0.0;  // up-facing triangles, projected
  double zMin = INFINITY, zMax = -INFINITY;
  double volume = 0.0;  // divergence theorem over the building's triangles
};

std::map<std::uint32_t, Stats> statsByTag(const Mesh& m) {
  std::map<std::uint32_t, Stats> out;
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    Stats& s = out[m.triangleTags[t]];
    const glm::dvec3 a = m.positions[m.triangles[t].x], b = m.positions[m.triangles[t].y],
                     c = m.positions[m.triangles[t].z];
    const glm::dvec3 n = glm::cross(b - a, c - a);  // twice the area, outward for CCW
    for (const glm::dvec3& p : {a, b, c}) {
      s.zMin = std::min(s.zMin, p.z);
      s.zMax = std::max(s.zMax, p.z);
    }
    s.volume += glm::dot(a, glm::cross(b, c)) / 6.0;
    const double len = glm::length(n);
    if (len == 0.0) continue;
    if (n.z < -0.99 * len) {
      s.floorArea += -n.z / 2.0;
      s.floorCentre += glm::dvec2(a + b + c) / 3.0 * (-n.z / 2.0);
    } else if (n.z > 0.0) {
      s.roofArea += n.z / 2.0;
    }
  }
  for (auto& [tag, s] : out)
    if (s.floorArea > 0.0) s.floorCentre /= s.floorArea;
  return out;
}

// An LOD2 house: a 10 x 6 m box of walls 5 m high under a gable roof (ridge along x at y = 3,
// 8 m above the floor; the gable ends are pentagons), a LOD1 block of the same house (which must not be read: LOD2 is
// higher), a BuildingPart (a 2 x 2 x 3 m shed) of the house, integer vertices with a transform.
const char* kHouse = R"({
  "type": "CityJSON", "version": "1.1",
  "metadata": {"referenceSystem": "https://www.opengis.net/def/crs/EPSG/0/2154"},
  "transform": {"scale": [0.5, 0.5, 0.25], "translate": [1000, 2000, 10]},
  "CityObjects": {
    "house": {"type": "Building", "children": ["shed"], "geometry": [
      {"type": "Solid", "lod": "1", "boundaries": [[[[0, 3, 2, 1]]]]},
      {"type": "Solid", "lod": "2.2", "boundaries": [[
        [[0, 3, 2, 1]],
        [[0, 1, 5, 4]], [[1, 2, 6, 9, 5]], [[2, 3, 7, 6]], [[3, 0, 4, 8, 7]],
        [[4, 5, 9, 8]], [[6, 7, 8, 9]]
      ]]}]},
    "shed": {"type": "BuildingPart", "parents": ["house"], "geometry": [
      {"type": "MultiSurface", "lod": 1, "boundaries": [
        [[10, 11, 12, 13]], [[14, 15, 16, 17], [18, 19, 20, 21]]]}]},
    "road": {"type": "Road", "geometry": [{"type": "MultiSurface", "lod": 1, "boundaries": [[[0, 1, 2]]]}]}
  },
  "vertices": [
    [0, 0, 0], [20, 0, 0], [20, 12, 0], [0, 12, 0],
    [0, 0, 20], [20, 0, 20], [20, 12, 20], [0, 12, 20],
    [0, 6, 32], [20, 6, 32],
    [30, 0, 0], [30, 4, 0], [34, 4, 0], [34, 0, 0],
    [30, 0, 12], [34, 0, 12], [34, 4, 12], [30, 4, 12],
    [31, 1, 12], [31, 3, 12], [33, 3, 12], [33, 1, 12]
  ]
})";

TEST(CityJson, ReadsTheHighestLodWithItsRoofExactly) {
  Diagnostics diag;
  const CityJsonBuildings b = parseCityJson(kHouse, "house.city.json", diag);
  EXPECT_TRUE(diag.ok()) << diag.errors.front();
  EXPECT_EQ(b.crs, "EPSG:2154");
  ASSERT_EQ(b.ids, std::vector<std::string>{"house"});  // the shed is part of the house, the road no building
  EXPECT_EQ(b.lods, std::vector<int>{2});
  const auto stats = statsByTag(b.mesh);
  ASSERT_EQ(stats.size(), 1u);
  const Stats& s = stats.at(0);
  // Vertices: index * scale + translate, e.g. [20, 12, 32] -> (1010, 2006, 18).
  EXPECT_DOUBLE_EQ(s.zMin, 10.0);
  EXPECT_DOUBLE_EQ(s.zMax, 18.0);
  // Floors: the house's 10 x 6 m and the shed's 2 x 2 m around (1016, 2001).
  EXPECT_DOUBLE_EQ(s.floorArea, 10.0 * 6.0 + 2.0 * 2.0);
  EXPECT_NEAR(s.floorCentre.x, (60.0 * 1005.0 + 4.0 * 1016.0) / 64.0, 1e-9);
  EXPECT_NEAR(s.floorCentre.y, (60.0 * 2003.0 + 4.0 * 2001.0) / 64.0, 1e-9);
  // Roof: the two slopes project onto the floor (60 m²) and the shed's top has a 1 x 1 m hole
  // (4 - 1 m²): the hole is kept out of the triangulation.
  EXPECT_NEAR(s.roofArea, 60.0 + 3.0, 1e-9);
  // The house is closed and outward: box 10 x 6 x 5 + prism 10 x (6 x 3 / 2); the shed is two
  // surfaces only (no volume of its own to count), so the volume is the house's alone.
  // House: floor 2, long walls 2 x 2, gable ends (pentagons) 2 x 3, roof 2 x 2; shed: floor 2,
  // top with a hole 8 (n + 2h - 2 for n = 8 vertices, h = 1 hole).
  EXPECT_EQ(b.mesh.triangles.size(), 16u + 2u + 8u);
  const double house = [&] {
    Mesh m = b.mesh;  // the house's surfaces only: the first 16 triangles
    m.triangles.resize(16);
    m.triangleTags.resize(16);
    return statsByTag(m).at(0).volume;
  }();
  EXPECT_NEAR(house, 10.0 * 6.0 * 5.0 + 10.0 * 6.0 * 3.0 / 2.0, 1e-9);
}

TEST(CityJson, BadInputIsNamedWithFileAndField) {
  Diagnostics diag;
  EXPECT_THROW(parseCityJson(R"({"type": "FeatureCollection"})", "x.json", diag), InputError);
  try {
    parseCityJson(R"({"type": "CityJSON", "CityObjects": {}, "vertices": [[0, 0]]})", "x.json", diag);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("x.json: vertices[0]: expected [x, y, z]"), std::string::npos) << e.what();
  }
  // One broken building is left out, named; the other is read.
  const CityJsonBuildings b = parseCityJson(R"({"type": "CityJSON", "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,1]],
    "CityObjects": {
      "bad": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": 1, "boundaries": [[[0, 1, 9]]]}]},
      "skew": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": 1, "boundaries": [[[0, 1, 2, 3]]]}]},
      "good": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": 1, "boundaries": [[[0, 1, 2]]]}]}}})",
                                            "y.json", diag);
  ASSERT_EQ(diag.errors.size(), 2u);
  EXPECT_NE(diag.errors[0].find(
                "y.json: CityObjects.bad.geometry[0].boundaries[0][0]: expected vertex indices below 4, got 9"),
            std::string::npos)
      << diag.errors[0];
  EXPECT_NE(diag.errors[1].find("CityObjects.skew.geometry[0].boundaries[0]: not planar"), std::string::npos)
      << diag.errors[1];
  EXPECT_EQ(b.mesh.triangles.size(), 1u);
}

// Delft's CityJSON 1.0 file (3dfier's LOD1 of the BGT footprints) against the same buildings as
// footprints with their 3dfier levels (buildings.geojson: z_base, z_top): both files are exports
// of one source at millimetre precision, so each building's footprint area, base and top agree to
// rounding (1e-6 relative, 1e-6 m), and the triangulated solids are closed (volume = area x height).
TEST(CityJson, DelftGivesTheBuildingsOfTheFootprintsAndHeights) {
  const std::string dir = testing::dataset("delft");
  if (dir.empty()) HV_SKIP_WITHOUT_DATA(std::string("no delft/ in ") + testing::dataDir() + " (set HISTOVIEW_DATA)");
  Diagnostics diag;
  const CityJsonBuildings city = readCityJson(dir + "/buildings.city.json", diag);
  EXPECT_TRUE(diag.ok()) << diag.errors.front();
  EXPECT_EQ(city.crs, "EPSG:7415");  // Amersfoort / RD New + NAP height
  EXPECT_EQ(city.ids.size(), 160u);
  FootprintFields fields;
  fields.height = "height";
  fields.base = "z_base";
  fields.top = "z_top";
  const std::vector<Footprint> footprints = readFootprints(dir + "/buildings.geojson", fields, diag);
  ASSERT_EQ(footprints.size(), 160u);
  const auto lod1 = statsByTag(buildLod1(footprints, nullptr, diag));
  const auto fromCity = statsByTag(city.mesh);
  ASSERT_EQ(fromCity.size(), 160u);
  std::set<std::uint32_t> matched;
  for (const auto& [tag, c] : fromCity) {
    // The footprint under the same floor (centres of different buildings are metres apart).
    const Stats* best = nullptr;
    std::uint32_t bestTag = 0;
    for (const auto& [ftag, f] : lod1)
      if (!best || glm::length(f.floorCentre - c.floorCentre) < glm::length(best->floorCentre - c.floorCentre)) {
        best = &f;
        bestTag = ftag;
      }
    ASSERT_LT(glm::length(best->floorCentre - c.floorCentre), 1e-3) << city.ids[tag];
    matched.insert(bestTag);
    EXPECT_NEAR(c.floorArea, best->floorArea, 1e-6 * best->floorArea) << city.ids[tag];
    EXPECT_NEAR(c.zMin, best->zMin, 1e-6) << city.ids[tag];
    EXPECT_NEAR(c.zMax, best->zMax, 1e-6) << city.ids[tag];
    EXPECT_NEAR(c.volume, c.floorArea * (c.zMax - c.zMin), 1e-6 * c.volume) << city.ids[tag];
  }
  EXPECT_EQ(matched.size(), 160u);  // one to one
}

// In a scene: buildings.path names the CityJSON file; its CRS (RD New + NAP) goes into the
// scene's (RD New) without a word, every building in.
TEST(CityJson, DelftSceneReadsTheCityJsonBuildings) {
  const std::string dir = testing::dataset("delft");
  if (dir.empty()) HV_SKIP_WITHOUT_DATA(std::string("no delft/ in ") + testing::dataDir() + " (set HISTOVIEW_DATA)");
  const auto tmp = std::filesystem::temp_directory_path() / ("hv-cityjson-" + std::to_string(::getpid()));
  std::filesystem::create_directories(tmp);
  std::ofstream(tmp / "scene.json") << R"({"crs": "EPSG:28992", "buildings": {"path": ")" << dir
                                    << R"(/buildings.city.json"}})";
  Diagnostics diag;
  const Scene scene = loadScene((tmp / "scene.json").string(), diag);
  std::filesystem::remove_all(tmp);
  EXPECT_TRUE(diag.ok()) << diag.errors.front();
  EXPECT_TRUE(diag.warnings.empty()) << diag.warnings.front();
  std::set<std::uint32_t> tags(scene.buildings.triangleTags.begin(), scene.buildings.triangleTags.end());
  EXPECT_EQ(tags.size(), 160u);
  EXPECT_EQ(scene.buildingValidity.size(), 160u);
  const Aabb b = scene.buildings.bounds();
  // RD New + NAP to RD New moves nothing: the file's extent of the buildings' vertices.
  EXPECT_NEAR(b.lo.x, 84825.872, 1e-6);
  EXPECT_NEAR(b.hi.x, 85056.513, 1e-6);
  EXPECT_NEAR(b.lo.y, 447456.724, 1e-6);
  EXPECT_NEAR(b.hi.y, 447624.074, 1e-6);
  EXPECT_NEAR(b.hi.z, 13.8, 1e-6);  // the tallest roof (buildings.geojson's largest z_top)
}

}  // namespace
}  // namespace hv
